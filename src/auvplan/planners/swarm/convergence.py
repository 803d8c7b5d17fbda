"""Whether a seeded plan has converged, by the run's own evidence (issue 59).

The seeded pipeline runs two searches that do not share their blind spots: the seeding lattice (a
shortest path over a coarse lattice of the whole box, :func:`~auvplan.planners.swarm.seeding.coarse_reference`)
and the swarm over the spline's control points.  Each is polished as a polyline at the end
(:mod:`auvplan.planners.swarm.polish`).  When they agree, or when the swarm's plan is the cheaper, the
plan is reported converged; otherwise the run says which evidence it has against its own plan, in
``PlanResult.converged`` (False) and ``PlanResult.convergence`` (the reason), which ``plan --json`` and
the results folder's ``metrics.json`` carry as ``converged`` and ``convergence``:

* ``no-lattice``: no seeding lattice of the ladder found a path (the swarm ran unseeded, and nothing
  checks the corridor it settled in);
* ``infeasible``: the swarm found no feasible path in its budget (the lattice path was returned, when
  there was one);
* ``corridors-disagree``: the seeding lattice's corridor, polished, ends more than
  :data:`CORRIDOR_MARGIN` below the swarm's own plan polished: the swarm did not converge to the
  cheaper corridor it was shown (the plan takes the lattice's, but no search has refined it beyond the
  light polish).

The evidence costs nothing beyond what the pipeline computes anyway (the polish's candidates' costs).
"""

from __future__ import annotations

import math

from ..core.base import PlanResult
from .polish import LATTICE_WITHIN, LatticeCorridor

__all__ = ["CORRIDOR_MARGIN", "STALL_ITERATIONS", "assess", "stalled_behind"]

CORRIDOR_MARGIN = 0.003
"""Relative margin by which the lattice's polished corridor must beat the swarm's polished plan to count as
evidence that the swarm has not converged (0.3 %, the issue's worst-case target)."""

STALL_ITERATIONS = 20
"""Iterations without an improvement of IABC's best after which the seeded pipeline, at its default budget,
asks :func:`stalled_behind` whether to stop the swarm.  On 144 plans of ``marcus-wake`` with 100-1 500
scattered zones (24 seeds each) every plan stopped at 20 kept the path it has with the whole budget; at 16,
9 of the same 144 did not (+0.35 % at worst: swarms that broke out of stalls of 12-16 iterations into a
cheaper corridor); ABC and PSO stopped at 20 changed 1 and 7 plans of 24 (up to +0.35 %), so the stop is
IABC's only (``python benchmarks/zones.py stall``; docs/zones.md)."""


def stalled_behind(corridor: LatticeCorridor, best: float) -> bool:
    """Whether a swarm stalled at ``best`` is behind the seeding lattice's corridor: the corridor, polished
    (once, kept for the final polish), ends more than :data:`CORRIDOR_MARGIN` below ``best``.

    The final polish would then return the corridor's path unless the swarm, spending the rest of its
    budget, found a path that polishes below it; a swarm that has not improved in
    :data:`STALL_ITERATIONS` iterations is stopped instead (the plan says so).  Not asked when the corridor's
    taut polygon is more than :data:`~auvplan.planners.swarm.polish.LATTICE_WITHIN` above ``best`` (the final
    polish would not polish it either).

    Parameters
    ----------
    corridor : LatticeCorridor
        The seeding lattice's corridor.
    best : float
        The swarm's best value so far.

    Returns
    -------
    bool
        True to stop the swarm.
    """
    return corridor.within(best) and corridor.polished_cost() < (1.0 - CORRIDOR_MARGIN) * best


def assess(result: PlanResult, seed_nodes: float, lattice_found: bool, fell_back: bool) -> tuple[bool | None, str]:
    """The convergence verdict of a seeded plan and its reason.

    Parameters
    ----------
    result : PlanResult
        The polished plan (its ``work`` holds the polish's ``polish_spline_cost`` and
        ``polish_lattice_cost`` when they were computed).
    seed_nodes : float
        Nodes of the seeding lattice that was used (the ladder's last rung when none found a path).
    lattice_found : bool
        Whether a seeding lattice found a path.
    fell_back : bool
        Whether the swarm found no feasible path (the lattice path returned in its place).

    Returns
    -------
    converged : bool or None
        False when any evidence says the plan may not be the best the run could reach; None when the
        polish was off (``spec.polish = 0``), so the corridors were not compared.
    reason : str
        ``"<code>: <explanation>"`` (codes in the module notes), or the agreement found.
    """
    if not lattice_found:
        return False, (f"no-lattice: no seeding lattice up to {seed_nodes:.0f} nodes found a path; the swarm "
                       "ran unseeded and nothing checks its corridor")
    if fell_back or not result.status.ok:
        return False, "infeasible: the swarm found no feasible path in its budget"
    if "polish_spline_cost" not in result.work:
        return None, "not assessed: without the polish (polish = 0) the corridors are not compared"
    spline = result.work["polish_spline_cost"]
    lattice = result.work.get("polish_lattice_cost", math.inf)
    if lattice < (1.0 - CORRIDOR_MARGIN) * spline:
        return False, (f"corridors-disagree: the seeding lattice's corridor, polished, is "
                       f"{100 * (1 - lattice / spline):.2f} % below the swarm's plan polished "
                       f"({lattice:.6g} against {spline:.6g}); the plan takes the lattice's")
    if math.isfinite(lattice):
        return True, (f"the swarm's plan and the seeding lattice's corridor, both polished, agree within "
                      f"{100 * CORRIDOR_MARGIN:.1f} % or the swarm's is the cheaper")
    return True, (f"the swarm's plan is feasible and the seeding lattice's corridor is more than "
                  f"{100 * LATTICE_WITHIN:.0f} % above it")
