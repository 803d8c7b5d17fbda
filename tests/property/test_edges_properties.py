"""Property tests over the dimensions the bugs of the survey/endurance/uncertainty/serve/geographic/ladder
wave hide in (issue 49): legs at different speeds and powers, positions either side of the antimeridian
and near the poles, non-square and rotated grids, currents that change in time, ladders whose coarse rung
wins, survey turns re-checked leg by leg, re-plans over their reserve.

Each property has an independent oracle (a closed form, a brute-force sum, the uncached computation);
hypothesis runs derandomized (the same examples every run) with small example counts, so the file
stays within a few seconds.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from pyproj import Geod

from auvplan._types import Status
from auvplan.endurance import EnergyModel, mission_budget
from auvplan.endurance.budget import traverse
from auvplan.endurance.pnr import point_of_no_return
from auvplan.path.flyable import VehicleLimits
from auvplan.path.legs import helm_check
from auvplan.world import Bounds, GriddedCurrent, Terrain, UniformCurrent, World
from helpers import flat_world

FAST = settings(max_examples=12, deadline=None, derandomize=True, database=None,
                suppress_health_check=[HealthCheck.too_slow])
WH = 3600.0


def _model(battery: float = 1000.0) -> EnergyModel:
    return EnergyModel(hotel_w=15.0, k=5.82, battery_wh=battery, usable_fraction=0.9, reserve=0.2)


def _open_world(size: float = 60_000.0, currents=None) -> World:  # type: ignore[no-untyped-def]
    w = flat_world(depth=500.0, size=size, min_altitude=5.0)
    w = replace(w, bounds=Bounds(-size, size, -size, size, -500.0, 0.0),
                terrain=Terrain(np.linspace(-size, size, 21), np.linspace(-size, size, 21), np.full((21, 21), -500.0)))
    return replace(w, currents=currents) if currents is not None else w


# ---------------------------------------------------------------------- 1. energy budget, per-leg speeds
legs_st = st.lists(st.tuples(st.floats(300.0, 4000.0), st.floats(-math.pi, math.pi), st.floats(-30.0, 30.0),
                             st.floats(0.7, 2.4)), min_size=2, max_size=5)


@FAST
@given(legs=legs_st, cu=st.floats(-0.4, 0.4), cv=st.floats(-0.4, 0.4))
def test_budget_charges_each_leg_at_its_own_speed_in_a_uniform_current(legs, cu, cv) -> None:  # type: ignore[no-untyped-def]
    """Each leg: V_g = c·ŝ + √(V² − |c⊥|²) (closed form), t = L / V_g, E = (P_hotel + k V³) t."""
    pts = [np.array([0.0, 0.0, -200.0])]
    for length, heading, dz, _ in legs:
        pts.append(pts[-1] + np.array([length * math.sin(heading), length * math.cos(heading), dz]))
    route, speeds = np.array(pts), np.array([leg[3] for leg in legs])
    world = _open_world(currents=UniformCurrent((cu, cv, 0.0)))
    b = mission_budget(world, route, _model(), speeds, 0.0, 100.0)
    c = np.array([cu, cv, 0.0])
    for i, v in enumerate(speeds):
        d = route[i + 1] - route[i]
        length = float(np.linalg.norm(d))
        e = d / length
        par = float(c @ e)
        vg = par + math.sqrt(v * v - (c @ c - par * par))
        t = length / vg
        assert b.t_end[i] - b.t_start[i] == pytest.approx(t, rel=1e-9)
        assert b.energy_leg_wh[i] == pytest.approx((15.0 + 5.82 * v**3) * t / WH, rel=1e-9)
    assert b.energy_wh == pytest.approx(float(np.sum(b.energy_leg_wh)), rel=1e-12)


# ---------------------------------------------------------------------- 2. point of no return, per-leg powers
@FAST
@given(lengths=st.lists(st.floats(1000.0, 5000.0), min_size=2, max_size=4),
       speeds=st.lists(st.floats(0.8, 2.4), min_size=4, max_size=4), back=st.floats(0.8, 2.4),
       q=st.floats(0.15, 0.9))
@example(lengths=[3000.0, 3000.0, 3000.0], speeds=[0.8, 2.4, 1.0, 1.0], back=1.5, q=0.6)
def test_point_of_no_return_sums_each_legs_own_power(lengths, speeds, back, q) -> None:  # type: ignore[no-untyped-def]
    """Straight out along x in still water at a speed per leg, straight back at ``back``:
    f(s) = Σ P(V_i) L_i / V_i (+ the part of the leg reached) + P(V_b) s / V_b − budget is piecewise
    linear and increasing; its root by hand within the bisection's 1 m."""
    n = len(lengths)
    v = np.array(speeds[:n])
    x = np.r_[0.0, np.cumsum(lengths)]
    route = np.column_stack([x, np.zeros(n + 1), np.full(n + 1, -200.0)])
    p = 15.0 + 5.82 * v**3
    e_out = np.r_[0.0, np.cumsum(p * np.diff(x) / v)] / WH  # at the vertices
    p_back = (15.0 + 5.82 * back**3) / back / WH  # Wh per metre back
    total = e_out[-1] + p_back * x[-1]
    model = _model(q * total / 0.7)  # budget = battery × (0.9 − 0.2)
    world = _open_world()
    tr = traverse(world, route, v, 0.0, 100.0)
    pnr = point_of_no_return(world, tr, model, speed=back, tol=0.5)
    f_vert = e_out + p_back * x - model.budget_wh
    k = int(np.flatnonzero(f_vert > 0)[0])  # the root lies on leg k - 1
    slope = p[k - 1] / v[k - 1] / WH + p_back
    s_star = x[k - 1] - f_vert[k - 1] / slope
    assert pnr.status is Status.EXACT and not pnr.whole_mission
    assert pnr.leg == k - 1
    assert pnr.s_m == pytest.approx(s_star, abs=1.0)


# ---------------------------------------------------------------------- 3. derived origin, antimeridian, poles
@FAST
@given(lat=st.floats(-84.0, 84.0), lon=st.floats(-180.0, 180.0), dlat=st.floats(-0.3, 0.3),
       dlon=st.floats(-0.4, 0.4))
@example(lat=15.0, lon=179.9, dlat=0.1, dlon=0.35)
@example(lat=-60.0, lon=-179.95, dlat=-0.2, dlon=-0.3)
def test_derived_origin_keeps_projected_distances_either_side_of_the_antimeridian(lat, lon, dlat, dlon) -> None:  # type: ignore[no-untyped-def]
    """Start and goal in degrees without [origin] (longitudes wrapped to [-180, 180], either side of
    ±180° and near the poles): the derived origin lies between them and the projected distance is
    the geodesic one (pyproj.Geod), within 0.5 %."""
    from auvplan.io.scenario.inputs.geoinput import resolve_positions

    lon2 = (lon + dlon + 180.0) % 360.0 - 180.0
    lat2 = lat + dlat
    data = {"mission": {"start": {"lat": lat, "lon": lon, "depth": 10.0},
                        "goal": {"lat": lat2, "lon": lon2, "depth": 10.0}}}
    geo = resolve_positions(data, "t.toml")
    assert geo is not None and geo.origin_derived
    olat, olon = geo.origin
    assert abs(olat - (lat + lat2) / 2) < 1e-9
    assert abs((olon - lon + 180.0) % 360.0 - 180.0) <= abs(dlon) + 1e-9  # between the two, on the short way
    a, b = (np.array(geo.metric["mission"][k][:2]) for k in ("start", "goal"))
    dist = Geod(ellps="WGS84").inv(lon, lat, lon2, lat2)[2]
    assert float(np.linalg.norm(b - a)) == pytest.approx(dist, rel=5e-3, abs=1.0)


# ---------------------------------------------------------------------- 4. survey turns, re-checked leg by leg
@FAST
@given(radius=st.floats(20.0, 300.0), spacing=st.floats(10.0, 900.0), heading=st.floats(-math.pi, math.pi),
       length=st.floats(800.0, 3000.0), dz=st.floats(-20.0, 20.0))
def test_survey_turns_fit_the_turn_radius_leg_by_leg(radius, spacing, heading, length, dz) -> None:  # type: ignore[no-untyped-def]
    """Two parallel lines joined by the survey's turn (lines `spacing` apart, any heading, narrower or
    wider than 2R): every waypoint of line end + turn + next line start fits a fly-by turn of R judged
    leg by leg (the check of `mission check`)."""
    from auvplan.survey.joins import turn_between

    u = np.array([math.sin(heading), math.cos(heading), 0.0])
    n = np.array([u[1], -u[0], 0.0])
    a = np.array([[0.0, 0.0, -50.0], [length / 2, 0.0, -50.0], [length, 0.0, -50.0]])
    a = a[:, :1] * u + np.array([0.0, 0.0, -50.0])
    b = a[::-1] + spacing * n + np.array([0.0, 0.0, dz])
    inner, _ = turn_between(a, b, radius)
    route = np.vstack([a, inner, b])
    rep = helm_check(route, VehicleLimits(90.0, radius), min_leg=0.0)
    assert rep.tightest_turn_m >= radius * (1.0 - 1e-9), rep.message


# ---------------------------------------------------------------------- 5. seabed sigma on non-square grids
@FAST
@given(dx=st.floats(50.0, 2000.0), aspect=st.floats(0.15, 6.0), gx=st.floats(-0.3, 0.3), gy=st.floats(-0.3, 0.3),
       floor=st.floats(0.0, 5.0), nx=st.integers(3, 9), ny=st.integers(3, 9))
@example(dx=100.0, aspect=4.0, gx=0.1, gy=0.05, floor=0.0, nx=5, ny=4)
def test_slope_sigma_on_non_square_rotated_planes(dx, aspect, gx, gy, floor, nx, ny) -> None:  # type: ignore[no-untyped-def]
    """On a plane z = gx x + gy y (any direction: a rotated slope) on a dx × aspect·dx grid:
    σ = √(σ₀² + (h |∇z| / 2)²) with h the larger spacing, at every node (closed form)."""
    from auvplan.world.uncertainty import slope_sigma, worst_case, z_score

    x = np.arange(nx) * dx
    y = 1000.0 + np.arange(ny) * dx * aspect
    z = -3000.0 + gx * x[None, :] + gy * y[:, None]
    t = Terrain(x, y, z)
    h = max(dx, dx * aspect)
    want = math.sqrt(floor**2 + (0.5 * h * math.hypot(gx, gy)) ** 2)
    s = slope_sigma(t, floor)
    assert s.shape == z.shape and np.allclose(s, want, rtol=1e-9, atol=1e-9)
    raised = worst_case(t, s, 0.9)
    assert np.allclose(raised.z - z, z_score(0.9) * want, rtol=1e-9, atol=1e-6)


# ---------------------------------------------------------------------- 6. a re-plan flight over its reserve
@FAST
@given(duration=st.floats(600.0, 40_000.0), battery=st.floats(20.0, 400.0), speed=st.floats(0.8, 2.2))
def test_a_flight_over_its_reserve_is_never_exact(duration, battery, speed) -> None:  # type: ignore[no-untyped-def]
    """A re-planning flight that reaches its goal: EXACT only when P(V) × duration ≤ the budget, else
    RESERVE_BROKEN, and the energy is P(V) × duration either way."""
    from auvplan.sim.ensemble.replan import ReplanParams, _finish
    from auvplan.sim.mission import Mission
    from auvplan.vehicles import VehicleParams

    world = _open_world(size=20_000.0)
    vehicle = VehicleParams(speed=speed, battery_wh=battery)
    mission = Mission("t", (0.0, 0.0, -100.0), (5000.0, 0.0, -100.0), vehicle=vehicle)
    xs = np.column_stack([np.linspace(0.0, 5000.0, 11), np.zeros(11), np.full(11, -100.0)])
    ts = np.linspace(0.0, duration, 11)
    f = _finish(world, world.currents, mission, ReplanParams(), 1, [xs], [ts], [], 0)
    model = EnergyModel.from_vehicle(vehicle)
    energy = float(model.power(speed)) * duration / WH
    assert f.energy_wh == pytest.approx(energy, rel=1e-12)
    assert f.status is (Status.EXACT if energy <= model.budget_wh else Status.RESERVE_BROKEN)


# ---------------------------------------------------------------------- 7. serve's energy cache, time-varying currents
def _tidal_world(period: float, amp: float) -> World:
    t = np.linspace(0.0, 4 * 3600.0, 9)
    x = np.linspace(-20_000.0, 20_000.0, 5)
    u = amp * np.sin(2 * np.pi * t / period)[:, None, None, None] * (1.0 + x / 40_000.0)[None, None, None, :] \
        * np.ones((1, 1, 5, 1))
    cur = GriddedCurrent(x, x, [0.0], u, 0.3 * u, t=t)
    return _open_world(size=20_000.0, currents=cur)


@FAST
@given(period=st.floats(1800.0, 14_400.0), amp=st.floats(0.05, 0.6),
       moves=st.lists(st.tuples(st.integers(1, 3), st.floats(-800.0, 800.0)), min_size=1, max_size=3))
def test_serve_energy_cache_equals_the_uncached_budget_in_a_time_varying_current(period, amp, moves) -> None:  # type: ignore[no-untyped-def]
    """The page's cached budget after each edit (a waypoint moved) equals mission_budget flown whole in
    a current that changes in time and place (a moved leg changes every later leg's timing)."""
    from auvplan.app.page.budget import IncrementalBudget

    world = _tidal_world(period, amp)
    model = _model()
    cache = IncrementalBudget(world, model, 200.0)
    w = np.array([[-8000.0, 0.0, -100.0], [-3000.0, 1000.0, -100.0], [2000.0, -500.0, -100.0],
                  [6000.0, 800.0, -100.0], [9000.0, 0.0, -100.0]])
    for k, dy in [(0, 0.0), *moves]:
        w = w.copy()
        w[k, 1] += dy
        got, _ = cache.run(w, 1.5)
        want = mission_budget(world, w, model, 1.5, 0.0, 200.0)
        assert got.status is want.status
        assert got.energy_wh == pytest.approx(want.energy_wh, rel=1e-9)
        assert np.allclose(got.t_end, want.t_end, rtol=1e-9)


# ---------------------------------------------------------------------- 8. the ladder's winner
@FAST
@given(costs=st.lists(st.floats(100.0, 200.0), min_size=2, max_size=5))
@example(costs=[150.0, 120.0])  # finest first: the coarser rung is cheaper
@example(costs=[150.0, 140.0, 110.0, 130.0])
def test_the_cheapest_rung_wins_the_ladder(costs, monkeypatch_session) -> None:  # type: ignore[no-untyped-def]
    """Rungs with given refined costs (finest first): the ladder's plan is the cheapest rung's (the
    coarser one on a tie), named in the message, and its history (coarse to fine) never rises."""
    from auvplan.planners import GridParams, PlannerSpec, PlanningProblem, plan_grid
    from auvplan.planners.core.base import PlanResult
    from auvplan.planners.grid import ladder

    cells = [100.0 * 2**i for i in range(len(costs))]
    cost_of = dict(zip(cells, costs))
    path = np.array([[100.0, 500.0, -50.0], [900.0, 500.0, -50.0]])

    def screened(problem, spec, model, rung, reference):  # type: ignore[no-untyped-def]
        return [(cost_of[rung.cell], 0, path, rung.cell)], 1, ""

    def finish(problem, spec, p, ref, levels, t0):  # type: ignore[no-untyped-def]
        return PlanResult(Status.EXACT, p, cost_of[ref], {}, 1, 1, 0.0, np.empty(0), "grid", message=f"cell {ref:g}")

    mp = monkeypatch_session
    mp.setattr(ladder, "_cells", lambda problem, params, reference: cells)
    mp.setattr(ladder, "_screened", screened)
    mp.setattr(ladder, "_converge", lambda problem, spec, raw, model, it, tol: (raw, None, 0))
    mp.setattr(ladder, "_finish", finish)
    world = flat_world(depth=100.0, size=1000.0)
    prob = PlanningProblem(world, path[0], path[1], 1.5)
    r = plan_grid(prob, PlannerSpec(name="grid", grid=GridParams(objective="length", cell=100.0)))
    best = min(costs)
    winner = max(c for c, v in cost_of.items() if v == best)  # coarse to fine: the coarser of equals
    assert r.cost == best and r.message.startswith(f"cell {winner:g}")
    assert f"best of the lattices at {', '.join(f'{c:g}' for c in cells)} m: {winner:g} m" in r.message
    assert r.history[-1] == best and np.all(np.diff(r.history[np.isfinite(r.history)]) <= 0.0)


@pytest.fixture(scope="module")
def monkeypatch_session():  # type: ignore[no-untyped-def]
    """A monkeypatch that lives across hypothesis examples (the function-scoped one may not)."""
    mp = pytest.MonkeyPatch()
    yield mp
    mp.undo()


# ---------------------------------------------------------------------- the modules' edges, pinned by hand
def test_uncertainty_rejects_what_it_cannot_use() -> None:
    """Confidence in (0, 1) for the quantile and (0.5, 1) for the worst case; σ finite and >= 0 (0 allowed,
    the nominal seabed); σ₀ >= 0."""
    from auvplan.world.uncertainty import slope_sigma, worst_case, z_score

    t = Terrain(np.array([0.0, 100.0, 200.0]), np.array([0.0, 400.0]), np.full((2, 3), -100.0))
    for bad in (0.0, 1.0):
        with pytest.raises(ValueError, match="must lie in \\(0, 1\\)"):
            z_score(bad)
    with pytest.raises(ValueError, match="floor_m"):
        slope_sigma(t, -1e-9)
    assert np.all(slope_sigma(t, 0.0) == 0.0)
    assert np.array_equal(worst_case(t, 0.0, 0.95).z, t.z)  # zero uncertainty: the nominal seabed
    for sigma in (np.array([[1.0, np.nan, 1.0], [1.0, 1.0, 1.0]]), np.array([[1.0, -1e-12, 1.0], [1.0, 1.0, 1.0]]),
                  np.array([[-1.0, -1.0, -1.0], [-1.0, -1.0, -1.0]])):
        with pytest.raises(ValueError, match="finite and >= 0"):
            worst_case(t, sigma, 0.95)
    for conf in (0.5, 1.0, 1.5):
        with pytest.raises(ValueError, match="must lie in \\(0.5, 1\\)"):
            worst_case(t, 1.0, conf)


@pytest.mark.parametrize("kind", ["none", "uniform", "gridded-steady", "gridded-one-time"])
def test_serve_cache_reuses_only_unchanged_legs_in_steady_fields(kind: str) -> None:
    """In a steady field the cached budget equals mission_budget (times and energies) and flies only the
    legs an edit changed (two when an interior waypoint moves); fields with a time axis are not steady."""
    from auvplan.app.page.budget import IncrementalBudget, steady

    x = np.linspace(-20_000.0, 20_000.0, 3)
    u = np.full((1, 1, 3, 3), 0.2) * np.linspace(0.5, 1.5, 3)[None, None, None, :]
    cur = {"none": None, "uniform": UniformCurrent((0.2, -0.1, 0.0)),
           "gridded-steady": GriddedCurrent(x, x, [0.0], u[0], 0.5 * u[0]),
           "gridded-one-time": GriddedCurrent(x, x, [0.0], u, 0.5 * u, t=[100.0])}[kind]
    world = _open_world(size=20_000.0)
    world = replace(world, currents=cur) if cur is not None else world
    assert steady(world.currents)
    cache = IncrementalBudget(world, _model(), 200.0)
    w = np.array([[-8000.0, 0.0, -100.0], [-3000.0, 1000.0, -100.0], [2000.0, -500.0, -100.0], [6000.0, 0.0, -100.0]])
    got, n = cache.run(w, 1.5)
    assert n == 3
    w2 = w.copy()
    w2[2, 1] += 300.0
    got2, n2 = cache.run(w2, np.array([1.5, 1.5, 1.5]))
    assert n2 == 2
    for g, route in ((got, w), (got2, w2)):
        want = mission_budget(world, route, _model(), 1.5, 0.0, 200.0)
        assert np.allclose(g.t_start, want.t_start, rtol=1e-12, atol=1e-9)
        assert np.allclose(g.t_end, want.t_end, rtol=1e-12) and g.energy_wh == pytest.approx(want.energy_wh, rel=1e-12)
        assert np.allclose(g.length_m, want.length_m, rtol=1e-12)
    t2 = GriddedCurrent(x, x, [0.0], np.concatenate([u, u]), np.concatenate([u, u]), t=[0.0, 10.0])
    assert not steady(t2)


def test_lru_cache_forgets_the_least_recently_used() -> None:
    from auvplan.app.page.lru import LruCache

    c = LruCache(size=2)
    c.put(b"a", (1.0,))
    c.put(b"b", (2.0,))
    found, missing = c.get_many([b"a", b"z"])  # a becomes the most recently used
    assert found == [(1.0,), None] and missing == [1]
    c.put(b"c", (3.0,))  # b, the least recently used, goes
    assert list(c.items) == [b"a", b"c"]


def test_a_re_plan_flight_is_judged_on_its_whole_track_and_its_arrival() -> None:
    """_finish by hand: a track that leaves the box or meets the seabed is a COLLISION with infinite
    arrival and the energy of the time flown (P(V) × last time); at exactly the arrival radius the
    flight has arrived (EXACT, arrival = the last time); short of it the vehicle homes on a plan and the
    arrival is the homing leg's end (later than the track's last time)."""
    from auvplan.sim.ensemble.replan import ReplanParams, _finish
    from auvplan.sim.mission import Mission
    from auvplan.vehicles import VehicleParams

    world = _open_world(size=20_000.0)
    vehicle = VehicleParams(speed=1.5)
    p_w = float(EnergyModel.from_vehicle(vehicle).power(1.5))
    mission = Mission("t", (0.0, 0.0, -100.0), (5000.0, 0.0, -100.0), vehicle=vehicle)
    ts = np.linspace(0.0, 3000.0, 11)
    out = np.column_stack([np.linspace(0.0, 30_000.0, 11), np.zeros(11), np.full(11, -100.0)])
    deep = np.column_stack([np.linspace(0.0, 5000.0, 11), np.zeros(11), np.r_[np.full(5, -100.0), -498.0,
                                                                              np.full(5, -100.0)]])
    for track, why in ((out, "operating box"), (deep, "seabed")):
        f = _finish(world, world.currents, mission, ReplanParams(), 1, [track], [ts], [], 0)
        assert f.status is Status.COLLISION and why in f.message and not f.arrived and not f.success
        assert f.energy_wh == pytest.approx(p_w * 3000.0 / WH, rel=1e-12)
    r = mission.sim.arrival_radius
    at = np.column_stack([np.linspace(0.0, 5000.0 - r, 11), np.zeros(11), np.full(11, -100.0)])
    f = _finish(world, world.currents, mission, ReplanParams(), 1, [at], [ts], [], 0)
    assert f.status is Status.EXACT and f.arrival_s == 3000.0 and f.replans == 0 and f.success
    short = at.copy()
    short[:, 0] *= 0.5
    f = _finish(world, world.currents, mission, ReplanParams(), 1, [short], [ts], [], 0)
    assert f.replans == 1 and f.arrived and f.arrival_s > 3000.0
    assert f.arrival_s == pytest.approx(3000.0 + (5000.0 - short[-1, 0]) / 1.5, rel=0.02)
    assert f.energy_wh == pytest.approx(p_w * f.arrival_s / WH, rel=1e-12)
    # the homing leg is appended node by node: no gap longer than a sub-step, one time per position
    assert f.track.shape[0] == f.times.shape[0] and f.times[-1] == f.arrival_s
    assert np.linalg.norm(np.diff(f.track, axis=0), axis=1).max() <= ReplanParams().ds + 1e-6
    assert np.linalg.norm(f.track[-1] - np.array(mission.goal)) <= r


def test_serve_cache_falls_back_to_the_whole_flight_where_the_current_beats_the_vehicle() -> None:
    """A 2 m/s eastward current against a 1.5 m/s vehicle on the westward leg: the cached budget is the
    whole flight's, INFEASIBLE with the same message (place and time) as mission_budget."""
    from auvplan.app.page.budget import IncrementalBudget

    world = _open_world(size=20_000.0, currents=UniformCurrent((2.0, 0.0, 0.0)))
    w = np.array([[-8000.0, 0.0, -100.0], [-3000.0, 0.0, -100.0], [-6000.0, 500.0, -100.0]])
    got, n = IncrementalBudget(world, _model(), 200.0).run(w, 1.5)
    want = mission_budget(world, w, _model(), 1.5, 0.0, 200.0)
    assert n == 2 and got.status is want.status is Status.INFEASIBLE and got.message == want.message
    assert "t = " in got.message and np.array_equal(got.t_end[:1], want.t_end[:1])
