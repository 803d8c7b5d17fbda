"""Plans that hold when the forecast is wrong (issue 39; ``docs/ensembles.md``).

* :mod:`~auvplan.sim.ensemble.score`: a route flown in every member of a current ensemble: arrival-time
  P50/P90 and the success probability (arrives, reserve kept, no collision);
* :mod:`~auvplan.sim.ensemble.robust`: one route for all members (``[planner] robust = "p90" | "success"``);
* :mod:`~auvplan.sim.ensemble.replan`: flying the truth while re-planning on the forecast in flight.
"""

from __future__ import annotations

from .robust import Candidate, RobustPlan, plan_robust, rank_key
from .score import EnsembleScore, MemberScore, percentile, score_route

__all__ = ["EnsembleScore", "MemberScore", "percentile", "score_route", "Candidate", "RobustPlan", "plan_robust",
           "rank_key"]
