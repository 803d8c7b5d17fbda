"""What every planner shares: the interface (:mod:`.base`), the settings of the methods (:mod:`.params`), the
registry, the plug-in point (:mod:`.registry`), the cost function and end-point check (:mod:`.common`), and the
zones' and the vehicle's last word on a plan (:mod:`.zone_check`, :mod:`.vehicle_limits`)."""

__all__: list[str] = []
