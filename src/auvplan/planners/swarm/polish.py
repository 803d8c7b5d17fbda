"""The seeded pipeline's last stage: the optimiser's spline polished as a polyline.

A clamped cubic B-spline with ``K`` control points cannot follow a corridor as closely as a
polyline: on the long hard scenarios the best splines end 0.2–0.7 % above the lattice reference,
which is a polyline refined to convergence.  The plan's path (its ``S`` samples) is therefore handed
to the lattice's own refinement (:func:`auvplan.planners.grid.planner.refine_plan`: cycles of an
elastic band at spacings 1/8 … 1/2048 of the length, each level kept only when cheaper and free)
with a light setting: ``spec.polish`` relaxation sweeps per level, levels down to 1/512 of the length
(:data:`POLISH_FINEST`) and one cycle (not when the start is
the goal: the band would shrink a loop to the point).  The polished
path is returned only when it is cheaper, passes the exact test and, when the vehicle has limits
(``problem.limits``: turn radius, pitch), is within them whenever the spline was, so the plan is never
worse, never less safe and never less flyable.  The work is not an objective evaluation of the
optimiser's problem: it is not counted in the budget and its CPU is reported apart
(``PlanResult.work["polish_cpu_s"]``).

The seeding lattice's own path is a second candidate (``lattice``): its taut polygon (document 004's
key waypoints), polished the same way with ``2 * spec.polish`` sweeps, wins where the spline cannot
take the route's detail.  On chagos-banks the cheap route climbs to the depth ceiling over a narrow
saddle 10 km before the goal (seabed 500 m deep under a 400 m ceiling and a 100 m altitude floor):
the splines of every seed pass beside it, 2–3 km longer, and no band move crosses the shoal between,
while the lattice's path already threads it (+0.05 % from the best known against the splines'
+0.08 … +0.36 %).  Its polish gives up (:func:`~auvplan.planners.grid.band.gives_up`) once the levels
left, each gaining as much as its best level so far, could not bring it below the best plan so far: there
it neither wins nor counts as evidence against convergence (:mod:`.convergence`).  On showcase it gains
nothing on its first level and stops there (1 level of 7); on 24 plans of the eight hard problems and 18
of nine short built-ins every plan was the same, to the bit, as with it run out.

The plan's own path lifted to the depth ceiling (interior points 1 m below it, :data:`LIFT_BELOW`; only
when the world has a ceiling) is a third candidate, polished first with ``spec.polish`` sweeps when its
cost is within :data:`LIFT_WITHIN` of the spline's; when it wins, the spline's own polish is not run (it
never beat the lifted one there), so the polish costs what it did before.  Under a ceiling the layer is
widest just below it, so a spline that passes round a rise deep down can cross it there: on
new-england-seamounts 4 seeds in 10 ended +0.38 … +0.54 % above the best known, going round a rise the
best known path crosses at the ceiling (wave 6's diagnosis), and their lifted paths, polished, end within
+0.12 %.  The cheapest of the polished paths is returned, under the same tests.
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from ..._types import FloatArray
from ...guidance.avoidance.local import key_waypoints
from ...path.flyable import check_limits
from ..core.base import PlannerSpec, PlanningProblem, PlanResult
from ..core.common import path_cost
from ..grid.planner import refine_plan

__all__ = ["LATTICE_WITHIN", "LIFT_BELOW", "LIFT_WITHIN", "POLISH_FINEST", "POLISH_TOLERANCE", "polish_polyline"]

POLISH_TOLERANCE = 0.5
"""Relative gain below which the lattice refinement stops after a cycle (0.5: after the first)."""

POLISH_FINEST = 512.0
"""The polish's finest level: every 1/512 of the length (the reference goes on to 1/2048).  The two finer
levels cost 45 % of the polish (their paths have 1 024 and 2 048 points) for 0.001–0.004 % of the cost on
chagos-banks and new-england-seamounts (6 seeds each)."""


LIFT_BELOW = 1.0
"""Depth (m) below the ceiling at which the lifted candidate's interior points are put."""

LIFT_WITHIN = 0.01
"""The plan lifted to the ceiling is polished only when its cost (one evaluation) is within this fraction
above the spline's.  On the six hard problems (4 seeds each) every lifted path within +0.9 % won after
polishing, against the spline's own polish too (new-england-seamounts, new-england-chain, ninetyeast-ridge
seeds 1–2, chagos-banks seeds 1–3), and every one from +2.0 % on lost or was not free (mariana-arc
+2.0 … +2.3 %, ninetyeast-ridge seeds 0 and 3, chagos-banks seed 0, marcus-wake-deep +7 … +8 %)."""

LATTICE_WITHIN = 0.03
"""The seeding lattice's taut polygon is polished only when its cost (one evaluation) is within this
fraction above the spline's: on the six hard problems the lattice's polished path won from +2.5 %
(chagos-banks) and lost from +3.6 % and more (ninetyeast-ridge, new-england-seamounts), where its
4-sweep polish was spent for nothing."""


def polish_polyline(problem: PlanningProblem, spec: PlannerSpec, result: PlanResult,
                    lattice: FloatArray | None = None) -> PlanResult:
    """The plan with its path polished as a polyline when that is cheaper and free.

    Parameters
    ----------
    problem : PlanningProblem
        World, start, goal and vehicle figures.
    spec : PlannerSpec
        The cost function; ``spec.polish`` relaxation sweeps per level (0: the plan unchanged).
    result : PlanResult
        An EXACT plan of the seeded pipeline.
    lattice : numpy.ndarray, optional
        The seeding lattice's path ``(N, 3)`` (m) from the start to the goal: its taut polygon,
        polished with ``2 * spec.polish`` sweeps, is the second candidate.

    Returns
    -------
    PlanResult
        The polished plan (a polyline: no control points, ``message`` says so) or ``result``, with
        ``work["polish_cpu_s"]`` set in both cases (``result`` itself when ``spec.polish`` is 0), and, for
        an EXACT plan, ``work["polish_spline_cost"]`` (the swarm's plan after its own or its lifted
        path's polish, the cheaper) and ``work["polish_lattice_cost"]`` (the lattice candidate polished;
        ``inf`` when the band found no free path; absent when it was not polished) for the convergence
        evidence (:mod:`auvplan.planners.swarm.convergence`).
    """
    if spec.polish == 0:
        return result
    c0 = time.process_time()
    out, costs = result, {}
    if result.status.ok and not np.array_equal(problem.start, problem.goal):  # a loop is not polished to a point
        lifted, second = _lifted_plan(problem, spec, result), _lattice_plan(problem, spec, result, lattice)
        spline = result.cost
        for candidate, sweeps, source in ((lifted, spec.polish, _LIFTED), (result, spec.polish, ""),
                                          (second, 2 * spec.polish, _LATTICE)):
            if candidate is None or (candidate is result and out is not result):
                continue  # the spline's own polish is not run when its lifted path, polished, already won
            settings = replace(spec, grid=replace(spec.grid, relax_iterations=sweeps, converge_tol=POLISH_TOLERANCE))
            target = out.cost if source == _LATTICE else None  # it must beat the best so far to count
            polished = refine_plan(problem, settings, candidate, finest=POLISH_FINEST, target=target)
            found = polished is not candidate and bool(np.isfinite(polished.cost))
            if source == _LATTICE:
                costs["polish_lattice_cost"] = polished.cost if found else float("inf")
            elif found:
                spline = min(spline, polished.cost)
            if found and polished.cost < out.cost and _flyable(problem, polished, result):
                note = (f"polished as a polyline (lattice band, {sweeps} sweeps per level"
                        f"{source}): {result.cost:.6g} -> {polished.cost:.6g}")
                out = replace(polished, message="; ".join(m for m in (result.message, note) if m),
                              control_points=None)
        costs["polish_spline_cost"] = spline
    return replace(out, work={**result.work, **costs, "polish_cpu_s": time.process_time() - c0})


_LATTICE = ", from the seeding lattice's taut path"
_LIFTED = ", from the plan lifted to the depth ceiling"


def _lattice_plan(problem: PlanningProblem, spec: PlannerSpec, result: PlanResult,
                  lattice: FloatArray | None) -> PlanResult | None:
    """The seeding lattice's taut polygon as a plan to polish (its cost ``inf``: the polish re-costs it), or
    None (no lattice, or its cost more than :data:`LATTICE_WITHIN` above ``result``'s)."""
    if lattice is None or lattice.shape[0] < 2:
        return None
    taut = key_waypoints(lattice, problem.world)
    if not path_cost(problem, spec, taut)["total"] <= (1.0 + LATTICE_WITHIN) * result.cost:
        return None  # too far above the spline for its polish to pay
    return replace(result, path=taut, cost=float("inf"), control_points=None)


def _lifted_plan(problem: PlanningProblem, spec: PlannerSpec, result: PlanResult) -> PlanResult | None:
    """The plan's path with its interior points lifted to 1 m below the depth ceiling, as a plan to polish
    (its cost ``inf``), or None (no ceiling, or its cost more than :data:`LIFT_WITHIN` above ``result``'s).

    Under a ceiling the layer is widest just below it (a rise or a seamount's flank is narrowest at its
    top), so a path that passes round a rise deep down can cross it there: on new-england-seamounts the
    splines of 4 seeds in 10 pass 100–300 m deeper round a rise that the best known path crosses at the
    ceiling, and no band move crosses between; lifted, the band finds the crossing."""
    ceiling = -problem.world.margins.min_depth - LIFT_BELOW
    if not np.isfinite(ceiling) or result.path.shape[0] < 3:
        return None
    path = np.array(result.path, dtype=float)
    path[1:-1, 2] = ceiling
    if not path_cost(problem, spec, path)["total"] <= (1.0 + LIFT_WITHIN) * result.cost:
        return None
    return replace(result, path=path, cost=float("inf"), control_points=None)


def _flyable(problem: PlanningProblem, polished: PlanResult, result: PlanResult) -> bool:
    """Whether ``polished`` is within the vehicle's limits whenever the spline ``result`` was."""
    lim = problem.limits
    return lim is None or check_limits(polished.path, lim).ok or not check_limits(result.path, lim).ok
