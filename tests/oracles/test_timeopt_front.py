"""The front method of the time-optimal planner (issue 55) and the one ground-speed function.

Oracle, independent of the planner: in a current uniform in space c(t) the points reachable at T
from the start form the disc of radius V T about ``start + D(T)``, ``D(T) = ∫ c dt``, so the least
time T* is the first root of ``|g − start − D(T)| − V T`` (scipy's ``brentq`` after a scan).  The
current is tabulated every 60 s (linear in between), and D is integrated *exactly* on that table
(trapezoids of a piecewise-linear function), so the oracle and the World agree to rounding.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from auvplan._types import Status
from auvplan.endurance import ground_speed
from auvplan.planners import PlannerSpec, PlanningProblem, plan
from auvplan.planners.core.params import TimeoptParams
from auvplan.planners.timeopt.front import build_grid, propagate
from auvplan.world import Bounds, GriddedCurrent, Margins, Sphere, World
from auvplan.world.currents.crab import HOLD, crab_speed, makes_headway

V = 1.0
TIDE = 44712.0  # M2 period (s)
W = 2.0 * math.pi / TIDE
START = np.array([0.0, 0.0, -50.0])

CASES = {  # name: (current (t) -> (u, v), goal (x, y), departure (s), box (xmin, xmax, ymin, ymax))
    "steady-stronger": (lambda t: (1.5, 0.6), (12000.0, 3000.0), 0.0, (-2000, 22000, -3000, 9000)),
    "reversing": (lambda t: (-1.2 * math.cos(W * t), 0.0), (12000.0, 0.0), 0.0, (-4000, 16000, -5000, 5000)),
    "rotary-behind-flood": (lambda t: (1.3 * math.cos(W * t), -1.3 * math.sin(W * t)), (-6000.0, 0.0), 0.0,
                            (-14000, 14000, -22000, 4000)),
    "cross-tide": (lambda t: (-1.2 * math.sin(W * t), 0.3), (12000.0, 0.0), 7200.0, (-6000, 16000, -4000, 8000)),
}


def world_of(cfun, box, tmax: float = 60000.0, dt: float = 60.0) -> tuple[World, np.ndarray, np.ndarray]:
    t = np.arange(0.0, tmax + dt, dt)
    c = np.array([cfun(s) for s in t])
    u = np.broadcast_to(c[:, 0, None, None, None], (t.size, 1, 2, 2)).copy()
    v = np.broadcast_to(c[:, 1, None, None, None], (t.size, 1, 2, 2)).copy()
    cur = GriddedCurrent([-1e5, 1e5], [-1e5, 1e5], [0.0], u, v, t=t)
    return World(Bounds(*box, -100, 0), currents=cur, margins=Margins(0, 0, 100)), t, c


def least_time(t: np.ndarray, c: np.ndarray, goal, depart: float, speed: float = V) -> float:
    """The oracle (module notes): first root of |g − D(T)| − V T, D exact on the piecewise-linear table."""
    cum = np.concatenate([[[0.0, 0.0]], np.cumsum(0.5 * (c[1:] + c[:-1]) * np.diff(t)[:, None], axis=0)])

    def drift(s: float) -> np.ndarray:
        k = min(int(s // (t[1] - t[0])), t.size - 2)
        a = (s - t[k]) / (t[k + 1] - t[k])
        return cum[k] + (t[k + 1] - t[k]) * (a * c[k] + 0.5 * a * a * (c[k + 1] - c[k]))

    g = np.asarray(goal, dtype=float) - START[:2]
    gap = lambda T: float(np.hypot(*(g - drift(depart + T) + drift(depart)))) - speed * T  # noqa: E731
    scan = np.linspace(1.0, t[-1] - depart - 1.0, 4000)
    k = int(np.flatnonzero(np.array([gap(T) for T in scan]) <= 0.0)[0])
    return float(brentq(gap, scan[k - 1], scan[k], xtol=1e-6))


def spec(depart: float, cell: float, **kw) -> PlannerSpec:
    return PlannerSpec(name="timeopt", timeopt=TimeoptParams(cell=cell, levels=1, depart_s=depart, dt=300.0, **kw))


@pytest.mark.parametrize("cell", [1000.0, 500.0])
@pytest.mark.parametrize("name", list(CASES))
def test_uniform_currents_within_one_percent_never_below(name, cell):
    """Every case at two resolutions: EXACT, within 1 % of the least time, never below it (up to the
    midpoint integrator's error, 10⁻⁵); the path passes the exact segment test."""
    cfun, goal, depart, box = CASES[name]
    world, t, c = world_of(cfun, box)
    exact = least_time(t, c, goal, depart)
    r = plan(PlanningProblem(world, START, np.array([*goal, -50.0]), speed=V), spec(depart, cell))
    assert r.status is Status.EXACT, r.message
    assert exact * (1 - 1e-5) <= r.cost <= 1.01 * exact
    assert world.segments_free(np.stack([r.path[:-1], r.path[1:]], axis=1), moving=False).all()


@pytest.mark.parametrize("name", ["steady-stronger", "reversing"])
def test_the_front_itself_arrives_at_the_least_time(name):
    """The front's interpolated arrival (before any refinement) within 0.3 % of the least time: a
    front that skips or repeats a time step is off by up to a step (1–2 %)."""
    cfun, goal, depart, box = CASES[name]
    world, t, c = world_of(cfun, box)
    exact = least_time(t, c, goal, depart)
    grid = build_grid(world, [box[0], box[2]], [box[1], box[3]], 500.0, (-50.0, -50.0), depart, 40000.0, 300.0)
    front = propagate(grid, START, goal, depart, V)
    assert abs(front.arrival - depart - exact) <= 3e-3 * exact


def test_unreachable_goal_is_infeasible_with_the_reason():
    """Upstream of a steady current stronger than the vehicle no heading gets anywhere: INFEASIBLE,
    the message saying why (the front's reachable set and the lattice), no nan."""
    world, _, _ = world_of(lambda s: (-1.3, 0.0), (-30000, 8000, -6000, 6000), tmax=30000.0)
    r = plan(PlanningProblem(world, START, np.array([6000.0, 0.0, -50.0]), speed=V),
             spec(0.0, 1000.0, horizon_s=8000.0))
    assert r.status is Status.INFEASIBLE
    assert "front:" in r.message and "reachable set" in r.message


def test_obstacle_respected_and_never_below_the_free_water_time():
    """A sphere across the way in a reversing current: EXACT, every segment free, the duration no less
    than the obstacle-free least time."""
    cfun, goal, depart, box = CASES["reversing"]
    world, t, c = world_of(cfun, box)
    world = World(world.bounds, currents=world.currents, obstacles=[Sphere((6000.0, 0.0, -50.0), 1500.0)],
                  margins=world.margins)
    r = plan(PlanningProblem(world, START, np.array([*goal, -50.0]), speed=V), spec(depart, 500.0))
    assert r.status is Status.EXACT, r.message
    assert world.segments_free(np.stack([r.path[:-1], r.path[1:]], axis=1), moving=False).all()
    assert r.cost >= least_time(t, c, goal, depart) * (1 - 1e-5)


def test_energy_objective_is_the_least_energy_over_the_speeds():
    """``objective = "energy"``: with P(v) = P_hotel + k v³ at a constant through-water speed, the plan's
    energy is the least over the allowed speeds of P(v) T*(v), T* the oracle's least time at v —
    within 1 %, never below it."""
    cfun, goal, depart, box = CASES["cross-tide"]
    world, t, c = world_of(cfun, box)
    problem = PlanningProblem(world, START, np.array([*goal, -50.0]), speed=V, hotel_power=5.0, drag_k=20.0)
    fractions = (0.8, 0.9, 1.0)
    r = plan(problem, spec(depart, 1000.0, objective="energy", speeds=fractions))
    assert r.status is Status.EXACT, r.message

    def energy(f: float) -> float:
        return (5.0 + 20.0 * (f * V) ** 3) * least_time(t, c, goal, depart, f * V)

    best = min(energy(f) for f in fractions)
    assert best * (1 - 1e-5) <= r.cost <= 1.01 * best


# --- the one ground-speed function (crab.py) ---------------------------------------------------------------


@pytest.mark.parametrize("c", [(0.3, 0.4, 0.0), (1.5, 0.6, 0.0), (-1.2, 0.2, 0.0), (0.0, 0.99, 0.0)])
def test_both_roots_hold_the_line_at_the_vehicle_speed(c):
    """Independent check: with ground speed g along ŝ the water-relative velocity g ŝ − c has norm V,
    for both roots; the near root is the larger."""
    e = np.array([1.0, 0.0, 0.0])
    near, far = (crab_speed(*c, *e, V, tail, 1.0) for tail in (False, True))
    for g in (near, far):
        assert np.linalg.norm(g * e - np.array(c)) == pytest.approx(V, rel=1e-12)
    assert near >= far


def test_one_feasibility_rule():
    """nan where the cross current passes hold·V (1 and the searches' 0.97); headway means g > 0;
    the energy check no longer floors at 1 µm/s (a slow leg is a long leg, not an impossible one)."""
    e = (1.0, 0.0, 0.0)
    assert math.isnan(crab_speed(0.0, 1.01, 0.0, *e, V, False, 1.0))
    assert math.isnan(crab_speed(0.0, 0.98, 0.0, *e, V, False, HOLD))
    assert not math.isnan(crab_speed(0.0, 0.98, 0.0, *e, V, False, 1.0))
    assert not makes_headway(math.nan) and not makes_headway(0.0) and makes_headway(1e-9)
    slow = np.array([-(1.0 - 5e-7), 0.0, 0.0])  # head current leaving 0.5 µm/s of headway
    assert ground_speed(slow, np.array(e), V) == pytest.approx(5e-7, rel=1e-6)
    assert math.isnan(ground_speed(np.array([-1.0, 0.0, 0.0]), np.array(e), V))
