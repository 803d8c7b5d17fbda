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

from ..._types import FloatArray, Status
from ...guidance.avoidance.local import key_waypoints
from ...path.flyable import check_limits
from ..core.base import PlannerSpec, PlanningProblem, PlanResult
from ..core.common import path_cost
from ..grid.planner import refine_plan

__all__ = ["LATTICE_WITHIN", "LIFT_BELOW", "LIFT_WITHIN", "POLISH_FINEST", "POLISH_TOLERANCE", "LatticeCorridor",
           "polish_polyline"]

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
                    lattice: FloatArray | None = None, corridor: LatticeCorridor | None = None) -> PlanResult:
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
    corridor : LatticeCorridor, optional
        The same lattice's corridor as the swarm's stall test saw it (:class:`LatticeCorridor`): its taut
        polygon and, when the test polished it, that polish, used instead of polishing it again.

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
        if corridor is None and lattice is not None:
            corridor = LatticeCorridor(problem, spec, lattice)
        lifted = _lifted_plan(problem, spec, result)
        second = None if corridor is None else corridor.candidate(result)
        spline = result.cost
        for candidate, sweeps, source in ((lifted, spec.polish, _LIFTED), (result, spec.polish, ""),
                                          (second, 2 * spec.polish, _LATTICE)):
            if candidate is None or (candidate is result and out is not result):
                continue  # the spline's own polish is not run when its lifted path, polished, already won
            polished = _polished(problem, spec, corridor if source == _LATTICE else None, candidate, sweeps, out.cost)
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


class LatticeCorridor:
    """The seeding lattice's taut polygon (document 004's key waypoints), costed once, and its polish, run
    out at most once, shared by the swarm's stall test (:func:`~auvplan.planners.swarm.convergence.stalled_behind`)
    and the final polish.

    Parameters
    ----------
    problem : PlanningProblem
        World, start, goal and vehicle figures.
    spec : PlannerSpec
        The cost function and ``spec.polish``.
    lattice : numpy.ndarray
        The seeding lattice's path ``(N, 3)`` (m) from the start to the goal.
    """

    def __init__(self, problem: PlanningProblem, spec: PlannerSpec, lattice: FloatArray) -> None:
        self._problem, self._spec, self._lattice = problem, spec, lattice
        self._taut: tuple[FloatArray, float] | None = None
        self._polished: PlanResult | None = None

    def taut(self) -> tuple[FloatArray, float] | None:
        """The taut polygon and its cost (one evaluation, made once).

        Returns
        -------
        tuple of (numpy.ndarray, float) or None
            The key waypoints ``(M, 3)`` (m) and their cost; None when there is no lattice path.
        """
        if self._lattice.shape[0] < 2:
            return None
        if self._taut is None:
            taut = key_waypoints(self._lattice, self._problem.world)
            self._taut = taut, float(path_cost(self._problem, self._spec, taut)["total"])
        return self._taut

    def within(self, cost: float) -> bool:
        """Whether the taut polygon costs at most :data:`LATTICE_WITHIN` above ``cost`` (else its polish does
        not pay).

        Parameters
        ----------
        cost : float
            A plan's cost.

        Returns
        -------
        bool
            False also when there is no lattice path.
        """
        taut = self.taut()
        return taut is not None and taut[1] <= (1.0 + LATTICE_WITHIN) * cost

    def candidate(self, result: PlanResult) -> PlanResult | None:
        """The taut polygon as a plan to polish.

        Parameters
        ----------
        result : PlanResult
            The plan whose fields the candidate takes and whose cost it is judged against.

        Returns
        -------
        PlanResult or None
            ``result`` with the taut polygon as its path and cost ``inf`` (the polish re-costs it); None when
            there is no lattice path or it costs more than :data:`LATTICE_WITHIN` above ``result``.
        """
        if not self.within(result.cost):
            return None  # too far above the spline for its polish to pay
        return replace(result, path=self.taut()[0], cost=float("inf"), control_points=None)  # type: ignore[index]

    def polished_cost(self) -> float:
        """The taut polygon's cost polished with ``2 * spec.polish`` sweeps per level and no target (made once,
        kept for :meth:`polished_plan`).

        Returns
        -------
        float
            The polished cost; ``inf`` when the band found no cheaper free path.
        """
        if self._polished is None:
            taut = self.taut()
            assert taut is not None
            bare = PlanResult(Status.EXACT, taut[0], float("inf"), {}, 0, 0, 0.0, np.empty(0), "lattice")
            self._polished = refine_plan(self._problem, _band(self._spec, 2 * self._spec.polish), bare,
                                         finest=POLISH_FINEST)
        return self._polished.cost

    def polished_plan(self, candidate: PlanResult) -> PlanResult | None:
        """``candidate`` as :func:`~auvplan.planners.grid.planner.refine_plan` run out would return it, from the
        polish :meth:`polished_cost` made.

        Parameters
        ----------
        candidate : PlanResult
            A plan from :meth:`candidate`.

        Returns
        -------
        PlanResult or None
            The polished plan (``candidate`` itself when the band found nothing); None when
            :meth:`polished_cost` has not run.
        """
        done = self._polished
        if done is None:
            return None
        if not np.isfinite(done.cost):
            return candidate  # the band found nothing: refine_plan returns its plan unchanged
        terms = {**candidate.cost_terms, **done.cost_terms}
        message = f"{candidate.message}; {done.message}".lstrip("; ")
        return replace(candidate, path=done.path, cost=done.cost, cost_terms=terms, control_points=None,
                       message=message)


def _polished(problem: PlanningProblem, spec: PlannerSpec, corridor: LatticeCorridor | None, candidate: PlanResult,
              sweeps: int, best: float) -> PlanResult:
    """``candidate`` polished with ``sweeps`` sweeps per level; the lattice's (``corridor`` given) must beat ``best``
    to count (a target: the band gives up), or is the polish the swarm's stall test made already, run out."""
    if corridor is None:
        return refine_plan(problem, _band(spec, sweeps), candidate, finest=POLISH_FINEST)
    ready = corridor.polished_plan(candidate)
    return ready if ready is not None else refine_plan(problem, _band(spec, sweeps), candidate, finest=POLISH_FINEST,
                                                       target=best)


def _band(spec: PlannerSpec, sweeps: int) -> PlannerSpec:
    """``spec`` with the polish's band settings: ``sweeps`` relaxation sweeps per level, one cycle."""
    return replace(spec, grid=replace(spec.grid, relax_iterations=sweeps, converge_tol=POLISH_TOLERANCE))


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
