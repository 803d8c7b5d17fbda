"""The seeded pipeline's last stage: the optimiser's spline polished as a polyline.

A clamped cubic B-spline with ``K`` control points cannot follow a corridor as closely as a
polyline: on the long hard scenarios the best splines end 0.2–0.7 % above the lattice reference,
which is a polyline refined to convergence.  The plan's path (its ``S`` samples) is therefore handed
to the lattice's own refinement (:func:`auvplan.planners.grid.planner.refine_plan`: cycles of an
elastic band at spacings 1/8 … 1/2048 of the length, each level kept only when cheaper and free)
with a light setting: ``spec.polish`` relaxation sweeps per level and one cycle (not when the start is
the goal: the band would shrink a loop to the point).  The polished
path is returned only when it is cheaper, passes the exact test and, when the vehicle has limits
(``problem.limits``: turn radius, pitch), is within them whenever the spline was, so the plan is never
worse, never less safe and never less flyable.  The work is not an objective evaluation of the
optimiser's problem: it is not counted in the budget and its CPU is reported apart
(``PlanResult.work["polish_cpu_s"]``).
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from ...flyable import check_limits
from ..base import PlannerSpec, PlanningProblem, PlanResult
from ..grid.planner import refine_plan

__all__ = ["POLISH_TOLERANCE", "polish_polyline"]

POLISH_TOLERANCE = 0.5
"""Relative gain below which the lattice refinement stops after a cycle (0.5: after the first)."""


def polish_polyline(problem: PlanningProblem, spec: PlannerSpec, result: PlanResult) -> PlanResult:
    """The plan with its path polished as a polyline when that is cheaper and free.

    Parameters
    ----------
    problem : PlanningProblem
        World, start, goal and vehicle figures.
    spec : PlannerSpec
        The cost function; ``spec.polish`` relaxation sweeps per level (0: the plan unchanged).
    result : PlanResult
        An EXACT plan of the seeded pipeline.

    Returns
    -------
    PlanResult
        The polished plan (a polyline: no control points, ``message`` says so) or ``result``, with
        ``work["polish_cpu_s"]`` set in both cases (``result`` itself when ``spec.polish`` is 0).
    """
    if spec.polish == 0:
        return result
    c0 = time.process_time()
    out = result
    if result.status.ok and not np.array_equal(problem.start, problem.goal):  # a loop is not polished to a point
        settings = replace(spec, grid=replace(spec.grid, relax_iterations=spec.polish, converge_tol=POLISH_TOLERANCE))
        polished = refine_plan(problem, settings, result)
        lim = problem.limits
        if polished is not result and (lim is None or check_limits(polished.path, lim).ok
                                       or not check_limits(result.path, lim).ok):
            note = f"polished as a polyline (lattice band, {spec.polish} sweeps per level): {result.cost:.6g} -> " \
                   f"{polished.cost:.6g}"
            out = replace(polished, message="; ".join(m for m in (result.message, note) if m))
    return replace(out, work={**result.work, "polish_cpu_s": time.process_time() - c0})
