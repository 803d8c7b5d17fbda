"""Navigation uncertainty: the dead-reckoning error budget along a mission, position fixes planned with
the fewest surfacings, and clearance under the error (issue 52; ``docs/navigation.md``).

* :mod:`~auvplan.nav.params`: ``[navigation]`` (:class:`NavParams`);
* :mod:`~auvplan.nav.budget`: σ linear in the distance travelled, per lock state, reset at fixes;
* :mod:`~auvplan.nav.clearance`: the seabed and obstacles within the horizontal error of each leg;
* :mod:`~auvplan.nav.fixes`: fewest fixes by dynamic programming, periodic fixes, the best period;
* :mod:`~auvplan.nav.mission`: a route's fixes, the mission that carries them, its check.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..runtime.lazy import lazy_attributes
from .params import NavParams, UsblParams

if TYPE_CHECKING:  # pragma: no cover - for type checkers only
    from .budget import ErrorProfile, NavBudget, error_profile, mission_budget
    from .clearance import leg_slack, safe_radius, uncertain_clearance
    from .fixes import FixPlan, apply_fixes, best_period, periodic_fixes, plan_fixes, route_profile
    from .mission import (
        NavCheck,
        NavPlan,
        check_navigation,
        fix_times,
        navigation_of,
        plan_navigation,
        surface_kinds,
    )

__all__ = ["NavParams", "UsblParams", "NavBudget", "ErrorProfile", "error_profile", "mission_budget",
           "safe_radius", "leg_slack", "uncertain_clearance", "FixPlan", "apply_fixes", "best_period",
           "periodic_fixes", "plan_fixes", "route_profile", "NavCheck", "NavPlan", "check_navigation", "fix_times",
           "navigation_of", "plan_navigation", "surface_kinds"]

_LAZY = {name: f"auvplan.nav.{module}" for module, names in (
    ("budget", ("ErrorProfile", "NavBudget", "error_profile", "mission_budget")),
    ("clearance", ("leg_slack", "safe_radius", "uncertain_clearance")),
    ("fixes", ("FixPlan", "apply_fixes", "best_period", "periodic_fixes", "plan_fixes", "route_profile")),
    ("mission", ("NavCheck", "NavPlan", "check_navigation", "fix_times", "navigation_of", "plan_navigation",
                 "surface_kinds"))) for name in names}
"""Loaded on first access: a scenario's ``[navigation]`` table (:class:`NavParams`) is read for every plan, its
budget and fixes computed for few (issue 56)."""


__getattr__, __dir__ = lazy_attributes(__name__, _LAZY, __all__)
