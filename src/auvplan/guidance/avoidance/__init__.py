"""Local avoidance of moving obstacles: key waypoints, APF, local minima and escape (document 004;
:mod:`.local`, its settings :mod:`.params`, its point model :mod:`.point_model`), predictive avoidance and
velocity obstacles within the vehicle's limits (:mod:`.predictive`, :mod:`.vo`), the movers' prediction
(:mod:`.turning`, :mod:`.sweep`) and the brute-force avoidability oracle (:mod:`.oracle`)."""

__all__: list[str] = []
