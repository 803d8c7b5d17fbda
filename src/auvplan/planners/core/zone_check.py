"""The zones' last word on every plan: a planner that cannot keep out of ``[[zones]]`` is refused, and a
plan whose polyline enters a zone is never reported feasible (the exact test of
:meth:`auvplan.world.Zones.entries` on every leg of :attr:`PlanResult.path`)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..._types import Status
from ...errors import ScenarioError
from .base import PlanningProblem, PlanResult
from .registry import REGISTRY, PlannerEntry

__all__ = ["refuse_unless_zones", "zone_entries", "hold_to_zones"]


def refuse_unless_zones(problem: PlanningProblem, entry: PlannerEntry) -> None:
    """Refuse a planner that cannot honour the world's zones.

    Parameters
    ----------
    problem : PlanningProblem
        Its world's zones.
    entry : PlannerEntry
        The planner (its ``"zones"`` capability).

    Raises
    ------
    ScenarioError
        If the world has zones and the planner does not keep out of them.
    """
    zones = problem.world.zones
    if zones and "zones" not in entry.capabilities:
        able = ", ".join(n for n, e in REGISTRY.items() if "zones" in e.capabilities)
        raise ScenarioError(f"planner {entry.name!r} cannot keep out of the scenario's {len(zones)} [[zones]] "
                            f"(first: {zones.names[0]!r}); choose one of {able}")


def zone_entries(problem: PlanningProblem, path: np.ndarray) -> list[tuple[int, str]]:
    """Every (leg, zone name) where the polyline enters a zone (legs numbered from 1).

    Parameters
    ----------
    problem : PlanningProblem
        The world's zones.
    path : numpy.ndarray
        Polyline ``(N, 3)`` (m).

    Returns
    -------
    list of (int, str)
        Entries in leg order; empty when the path keeps out (or there are no zones).
    """
    zones = problem.world.zones
    p = np.asarray(path, dtype=float).reshape(-1, 3)
    if not zones or p.shape[0] < 2:
        return []
    seg, zi = zones.entries(np.stack([p[:-1], p[1:]], axis=1))
    return [(int(s) + 1, zones.names[int(z)]) for s, z in zip(seg, zi, strict=True)]


def hold_to_zones(problem: PlanningProblem, result: PlanResult) -> PlanResult:
    """A successful plan that enters a zone becomes ``INFEASIBLE`` naming the zone and the leg.

    Parameters
    ----------
    problem : PlanningProblem
        The world's zones.
    result : PlanResult
        Any planner's result.

    Returns
    -------
    PlanResult
        With zones, a copy whose ``cost_terms`` hold ``zone_clearance_min_m`` (the path's least
        distance to the zones themselves, :meth:`Zones.clearance`), and with status ``INFEASIBLE``
        and the entries in its message when it enters one (with the planners' pad).
    """
    zones = problem.world.zones
    if not zones or np.asarray(result.path).size == 0:
        return result
    clearance = zones.exact.clearance(result.path)
    result = replace(result, cost_terms=dict(result.cost_terms, zone_clearance_min_m=clearance))
    hits = zone_entries(problem, result.path) if result.status.ok else []
    if not hits:
        return result
    where = "; ".join(f"leg {leg} enters zone {name!r}" for leg, name in hits[:5])
    more = f" (and {len(hits) - 5} more)" if len(hits) > 5 else ""
    terms = dict(result.cost_terms, violations=float(len(hits)), collisions=float(len(hits)))
    return replace(result, status=Status.INFEASIBLE, cost_terms=terms,
                   message=f"{result.message + '; ' if result.message else ''}{where}{more}")
