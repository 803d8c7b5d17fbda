"""The energy budget's input checks and edge cases by hand (issue 49's mutation run of ``endurance``)."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.endurance.budget import traverse
from auvplan.world import Bounds, World

WORLD = World(Bounds(-1000, 1000, -1000, 1000, -200, 0))
PTS = np.array([[0.0, 0.0, -50.0], [100.0, 0.0, -50.0], [200.0, 0.0, -50.0]])


@pytest.mark.parametrize("speeds", [[1.0, 0.0], [0.0, 1.0], [1.0, -1.0], [1.0, np.nan], [1.0, np.inf]])
def test_traverse_refuses_any_leg_speed_that_is_not_positive_and_finite(speeds) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ValueError, match="leg speeds and ds must be positive"):
        traverse(WORLD, PTS, speeds, 0.0, 10.0)


def test_traverse_in_still_water_takes_length_over_speed_per_leg() -> None:
    tr = traverse(WORLD, PTS, [1.0, 2.0], 100.0, 10.0)
    assert tr.ok and tr.times.tolist() == pytest.approx([100.0, 200.0, 250.0])


def test_traverse_samples_the_current_at_each_steps_midpoint() -> None:
    """A following current growing linearly along the leg, u = 1e-3 x (m/s): the time over 0 <= x <= 200 m at
    V = 1 m/s is ∫ dx / (1 + 1e-3 x) = ln(1.2) / 1e-3 = 182.32 s (midpoint steps of 10 m: within 0.01 s)."""
    from auvplan.world import GriddedCurrent

    x = np.array([-1000.0, 1000.0])
    u = np.broadcast_to(1e-3 * x, (1, 2, 2)).copy()
    world = World(Bounds(-1000, 1000, -1000, 1000, -200, 0),
                  currents=GriddedCurrent(x, np.array([-1000.0, 1000.0]), np.array([0.0]), u, np.zeros_like(u)))
    tr = traverse(world, PTS[[0, 2]], 1.0, 0.0, 10.0)
    assert tr.times[-1] == pytest.approx(np.log(1.2) / 1e-3, abs=0.01)


def test_reserve_broken_names_the_leg_where_the_reserve_is_entered() -> None:
    """90 % usable, 20 % reserve: 70 % of the battery to spend.  Three 1 km legs at 1 m/s in still water, each
    (15 + 5.82) W × 1000 s = 5.78 Wh, the battery sized so that 2.5 legs use the 70 %: the reserve is entered on
    leg 2: the message says so; the point of no return of a mission that cannot come back from the start is
    INFEASIBLE and does not claim the whole mission."""
    from auvplan._types import Status
    from auvplan.endurance.budget import budget_of
    from auvplan.endurance.pnr import point_of_no_return
    from auvplan.endurance.power import EnergyModel

    pts = np.array([[0.0, 0.0, -50.0], [1000.0, 0.0, -50.0], [2000.0, 0.0, -50.0], [3000.0, 0.0, -50.0]])
    leg_wh = (15.0 + 5.82) * 1000.0 / 3600.0  # P(1 m/s) over 1000 s
    battery = 2.5 * leg_wh / 0.7  # 70 % of it is 2.5 legs: the reserve is entered half-way along leg 2
    model = EnergyModel(battery_wh=battery)
    tr = traverse(WORLD, pts, 1.0, 0.0, 100.0)
    b = budget_of(tr, model)
    assert b.status is Status.RESERVE_BROKEN and "the reserve is entered on leg 2" in b.message, b.message
    tiny = EnergyModel(battery_wh=0.5 * leg_wh)
    pnr = point_of_no_return(WORLD, tr, tiny, recovery=pts[-1])  # the boat waits 3 km away
    assert pnr.status is Status.INFEASIBLE and pnr.whole_mission is False and pnr.s_m == 0.0


def test_a_pure_hold_has_no_ground_speed_and_a_budget_used_to_rounding_is_exact() -> None:
    """A leg of zero length held 60 s (a hold at a waypoint): its mean speed over ground is undefined (NaN, not
    0 m/s), its energy the hotel load P(0) x 60 s; the next 100 m at 1 m/s: 1 m/s, (15 + 5.82) W x 100 s.  A
    battery whose budget is the flight's energy less 1e-9 Wh (rounding, under 1e-9 of the battery) is EXACT."""
    from auvplan._types import Status
    from auvplan.endurance.budget import budget_of
    from auvplan.endurance.power import EnergyModel

    pts = PTS[[0, 0, 1, 2]]
    tr = traverse(WORLD, pts, 1.0, 0.0, 10.0, dwell=[60.0, 0.0, 0.0, 0.0])
    b = budget_of(tr, EnergyModel())
    assert np.isnan(b.speed_ground[0]) and b.speed_ground[1:].tolist() == pytest.approx([1.0, 1.0])
    assert b.energy_leg_wh.tolist() == pytest.approx([15.0 * 60.0 / 3600.0] + [20.82 * 100.0 / 3600.0] * 2)
    used = float(b.cumulative_wh[-1])
    tight = EnergyModel(battery_wh=(used - 1e-9) / 0.7)  # budget = battery x (0.9 usable - 0.2 reserve)
    assert tight.budget_wh < used and used - tight.budget_wh < 1e-9 * tight.battery_wh
    assert budget_of(tr, tight).status is Status.EXACT
    assert budget_of(tr, EnergyModel(battery_wh=(used - 1e-6) / 0.7)).status is Status.RESERVE_BROKEN


def test_point_of_no_return_is_the_first_crossing_when_the_way_back_costs_more_per_metre() -> None:
    """Out 2.5 km east at 1 m/s, back home, then 5 km north; the return at 2.4 m/s costs more per metre
    (b = P(2.4)/2.4 = 39.8 J/m) than going out (a = P(1)/1 = 20.8 J/m), so f(s) = a s + b d(s) - B rises to
    2.5 km, falls back to home (5 km) and rises again: not monotonic.  With B = 35 Wh the first crossing is
    s* = B / (a + b) = 2 080 m (the documented conservative answer), not the later one at 5 362 m."""
    from auvplan._types import Status
    from auvplan.endurance.pnr import point_of_no_return
    from auvplan.endurance.power import EnergyModel

    world = World(Bounds(-10000, 10000, -10000, 10000, -200, 0))
    pts = np.array([[0.0, 0.0, -50.0], [2500.0, 0.0, -50.0], [0.0, 0.0, -50.0], [0.0, 5000.0, -50.0]])
    model = EnergyModel(battery_wh=35.0 / 0.7)
    tr = traverse(world, pts, 1.0, 0.0, 100.0)
    a, b = float(model.power(1.0)) / 3600.0, float(model.power(2.4)) / 2.4 / 3600.0  # Wh per metre
    assert 5000.0 * a < model.budget_wh < 2500.0 * (a + b)  # home at 5 km is inside the budget again
    pnr = point_of_no_return(world, tr, model, speed=2.4)
    assert pnr.status is Status.EXACT and pnr.leg == 0 and not pnr.whole_mission
    assert pnr.s_m == pytest.approx(model.budget_wh / (a + b), abs=1.0)


def test_the_way_back_retraces_the_dive_to_the_vertex_that_sees_the_rally_point() -> None:
    """A ridge at x = 500 m (crest 55.1 m deep, 5 m minimum altitude) that a level leg at 50 m clears by 5.1 m.
    The route runs from x = -500 m east to x = 1000 m, dives 10 m, then heads north at 60 m; the rally point is at
    x = 0.  Half a metre along the northward leg the straight line to it passes the crest 0.1 m above (blocked),
    and so does the line from the bottom of the dive; the vertex at 50 m sees it: the way back retraces 0.5 m and
    the 10 m dive and flies 1000 m home, 1010.5 m at 1 m/s: P(1) x 1010.5 s (not the corner cut to the top of
    the dive, 1010.01 m, nor the straight line through the margin, nor the retrace on to the start)."""
    from auvplan.endurance.pnr import _return_energy
    from auvplan.endurance.power import EnergyModel
    from auvplan.world import Margins, Terrain

    x = np.arange(-1000.0, 2001.0, 500.0)
    z = np.where(x == 500.0, -55.1, -100.0)[None, :].repeat(3, axis=0)
    world = World(Bounds(-1000, 2000, -1000, 1000, -200, 0), Terrain(x, np.array([-1000.0, 0.0, 1000.0]), z),
                  margins=Margins(min_altitude=5.0))
    pts = np.array([[-500.0, 0.0, -50.0], [1000.0, 0.0, -50.0], [1000.0, 0.0, -60.0], [1000.0, 300.0, -60.0]])
    rally = np.array([0.0, 0.0, -50.0])
    free_from = np.array([world.path_free(np.stack([q, rally])) for q in pts])
    assert world.path_free(pts) and free_from.tolist() == [True, True, False, False]
    assert not world.path_free(np.array([[1000.0, 0.5, -60.0], rally]))
    tr = traverse(world, pts, 1.0, 0.0, 100.0)
    e_out, e_ret, pos, t, leg = _return_energy(world, tr, EnergyModel(), 1510.5, rally, 1.0, free_from, 100.0)
    assert leg == 2 and pos.tolist() == pytest.approx([1000.0, 0.5, -60.0]) and t == pytest.approx(1510.5)
    assert e_out == pytest.approx(20.82 * 1510.5 / 3600.0, rel=1e-9)
    assert e_ret == pytest.approx(20.82 * 1010.5 / 3600.0, rel=1e-9)


def test_positions_along_the_flight_by_distance() -> None:
    """Traverse.at: the start at s <= 0, linear along each leg, the end past the route's length; a route ending
    with a held zero-length leg (a surface fix at the last vertex) ends at that vertex."""
    tr = traverse(WORLD, PTS[[0, 1, 2, 2]], [1.0, 2.0, 1.0], 0.0, 10.0, dwell=[0.0, 0.0, 30.0, 0.0])
    for s, where, t in ((-5.0, PTS[0], 0.0), (0.0, PTS[0], 0.0), (0.5, [0.5, 0.0, -50.0], 0.5),
                        (150.0, [150.0, 0.0, -50.0], 125.0), (1e6, PTS[2], 150.0), (200.0, PTS[2], 150.0)):
        pos, at_t, _ = tr.at(s)
        assert pos.tolist() == pytest.approx(list(where)) and at_t == pytest.approx(t), s


def test_optimal_speed_is_the_least_energy_per_metre() -> None:
    """v* = (P_hotel / (2 k))^(1/3) minimises (P_hotel + k v³) / v: against a bounded scalar minimisation."""
    from scipy.optimize import minimize_scalar

    from auvplan.endurance.power import optimal_speed

    for hotel, k in ((15.0, 5.82), (40.0, 2.0), (5.0, 20.0)):
        best = minimize_scalar(lambda v, h=hotel, kk=k: (h + kk * v**3) / v, bounds=(0.05, 10.0), method="bounded",
                               options={"xatol": 1e-9})
        assert optimal_speed(hotel, k) == pytest.approx(best.x, rel=1e-5)
    assert optimal_speed(15.0, 5.82) == pytest.approx((15.0 / 11.64) ** (1 / 3)) and optimal_speed(0.0, 3.0) == 0.0


def _blocked_world() -> World:
    """A current against +x of 1.5 m/s from x = 400 to 600 m (0 at 300 and 700 m, linear between nodes)."""
    from auvplan.world import GriddedCurrent

    x = np.arange(-1000.0, 1001.0, 100.0)
    u = np.where((x >= 400.0) & (x <= 600.0), -1.5, 0.0)
    u = np.broadcast_to(u, (1, 2, x.size)).copy()
    return World(Bounds(-1000, 1000, -1000, 1000, -200, 0),
                 currents=GriddedCurrent(x, np.array([-1000.0, 1000.0]), np.array([0.0]), u, np.zeros_like(u)))


def test_the_flight_stops_where_the_current_first_beats_the_vehicle() -> None:
    """At 1 m/s along +x the current beats the vehicle from x = 366.7 m (u = -1.5 (x - 300) / 100 = -1): the
    10 m step from 370 m is the first that cannot be flown; the flight ends there (no later vertex has a
    time, the route's flown length is 370 m), and the message names leg 0 at 370 m, not a later point or leg."""
    route = np.array([[0.0, 0.0, -50.0], [1000.0, 0.0, -50.0], [1000.0, 500.0, -50.0]])
    tr = traverse(_blocked_world(), route, 1.0, 0.0, 10.0)
    assert not tr.ok and tr.message.startswith("leg 0: the current beats the vehicle at [370.0, 0.0, -50.0]")
    assert np.isnan(tr.times[1:]).all() and tr.node_s[-1] == pytest.approx(370.0)


def test_traverse_samples_the_current_at_the_midpoint_of_a_diagonal_step() -> None:
    """A following current u = 1e-3 x on a leg along (0.6, 0.8): V_g = 0.6 u + √(1 − (0.8 u)²); the time over
    1000 m against the integral of 1 / V_g by quadrature (midpoint steps of 10 m: within 0.01 s)."""
    from scipy.integrate import quad

    from auvplan.world import GriddedCurrent

    x = np.array([-1000.0, 1000.0])
    u = np.broadcast_to(1e-3 * x, (1, 2, 2)).copy()
    world = World(Bounds(-1000, 1000, -1000, 1000, -200, 0),
                  currents=GriddedCurrent(x, np.array([-1000.0, 1000.0]), np.array([0.0]), u, np.zeros_like(u)))
    route = np.array([[0.0, 0.0, -50.0], [600.0, 800.0, -50.0]])
    tr = traverse(world, route, 1.0, 0.0, 10.0)
    expect = quad(lambda s: 1.0 / (0.6e-3 * 0.6 * s + np.sqrt(1.0 - (0.8e-3 * 0.6 * s) ** 2)), 0.0, 1000.0)[0]
    assert tr.times[-1] == pytest.approx(expect, abs=0.01)


def test_a_leg_ending_exactly_on_the_reserve_does_not_enter_it() -> None:
    """Three 1 km legs at 1 m/s (5.78 Wh each), the battery sized so that two legs use exactly the 70 % between
    usable and reserve: the second leg ends on the reserve, the third enters it (named)."""
    from auvplan._types import Status
    from auvplan.endurance.budget import budget_of
    from auvplan.endurance.power import EnergyModel

    pts = np.array([[0.0, 0.0, -50.0], [1000.0, 0.0, -50.0], [2000.0, 0.0, -50.0], [3000.0, 0.0, -50.0]])
    tr = traverse(WORLD, pts, 1.0, 0.0, 100.0)
    two = float(budget_of(tr, EnergyModel()).cumulative_wh[1])
    model = EnergyModel(battery_wh=two / 0.7)
    b = budget_of(tr, model)
    assert abs(b.remaining_wh[1] - model.reserve_wh) < 1e-12 * model.battery_wh
    assert b.status is Status.RESERVE_BROKEN and "the reserve is entered on leg 2" in b.message, b.message


def test_route_and_step_checks_and_the_ground_speed_of_each_current_component() -> None:
    """One point is not a route; ds must be positive (0.5 m is); a 6-point route without holds; the ground speed
    along north in a northward current adds it (V + v), along east in it crabs (√(V² − v²)), an up current
    along north is cross current."""
    from auvplan.endurance.budget import ground_speed

    with pytest.raises(ValueError, match="at least 2 points"):
        traverse(WORLD, PTS[:1], 1.0, 0.0, 10.0)
    for ds in (0.0, -1.0):
        with pytest.raises(ValueError, match="ds must be positive"):
            traverse(WORLD, PTS, 1.0, 0.0, ds)
    assert traverse(WORLD, PTS, 1.0, 0.0, 0.5).times[-1] == pytest.approx(200.0)
    six = np.array([[100.0 * k, 50.0 * (k % 2), -50.0] for k in range(6)])
    tr = traverse(WORLD, six, 2.0, 10.0, 10.0)
    assert tr.ok and tr.times[-1] == pytest.approx(10.0 + 5 * np.hypot(100.0, 50.0) / 2.0)
    north, east = np.array([0.0, 1.0, 0.0]), np.array([1.0, 0.0, 0.0])
    assert ground_speed(np.array([0.0, 0.5, 0.0]), north, 1.0) == pytest.approx(1.5)
    assert ground_speed(np.array([0.0, 0.6, 0.0]), east, 1.0) == pytest.approx(0.8)
    assert ground_speed(np.array([0.0, 0.0, 0.6]), north, 1.0) == pytest.approx(0.8)


def test_short_legs_short_holds_and_the_power_law() -> None:
    """A 0.5 m leg at 1 m/s is flown at 1 m/s over ground (its 0.5 s is a moving time like any other); a hold of
    0.5 s delays what follows by 0.5 s; P(V) = P_hotel + k V³ at 2 m/s: 15 + 5.82 x 8 W."""
    from auvplan.endurance.budget import budget_of
    from auvplan.endurance.power import EnergyModel

    pts = np.array([[0.0, 0.0, -50.0], [0.5, 0.0, -50.0], [100.5, 0.0, -50.0]])
    tr = traverse(WORLD, pts, 1.0, 0.0, 10.0, dwell=[0.0, 0.5, 0.0])
    assert tr.times.tolist() == pytest.approx([0.0, 0.5, 101.0])
    assert budget_of(tr, EnergyModel()).speed_ground.tolist() == pytest.approx([1.0, 1.0])  # held time excluded
    assert float(EnergyModel().power(2.0)) == pytest.approx(15.0 + 5.82 * 8.0)


def test_the_midpoint_sample_is_taken_half_a_step_later_in_a_current_changing_in_time() -> None:
    """A following current growing in time, u = 1e-3 t (uniform in space): ds/dt = 1 + 1e-3 t, so 1000 m take
    t = (√(1 + 2e-3 x 1000) − 1) / 1e-3 = 732.05 s (midpoint steps of 10 m in space and half a step in time:
    within 0.05 s)."""
    from auvplan.world import GriddedCurrent

    t_axis = np.array([0.0, 5000.0])
    u = np.broadcast_to((1e-3 * t_axis)[:, None, None, None], (2, 1, 2, 2)).copy()
    xy = np.array([-1000.0, 1000.0])
    world = World(Bounds(-1000, 1000, -1000, 1000, -200, 0),
                  currents=GriddedCurrent(xy, xy, np.array([0.0]), u, np.zeros_like(u), t=t_axis))
    tr = traverse(world, np.array([[-500.0, 0.0, -50.0], [500.0, 0.0, -50.0]]), 1.0, 0.0, 10.0)
    assert tr.times[-1] == pytest.approx((np.sqrt(3.0) - 1.0) / 1e-3, abs=0.05)


def test_positions_along_one_step_legs_that_turn() -> None:
    """With one sub-step per leg (ds longer than every leg) Traverse.at interpolates between the vertices of
    the leg the distance falls on, not an extrapolation of the next or the previous leg."""
    pts = np.array([[0.0, 0.0, -50.0], [100.0, 0.0, -50.0], [100.0, 100.0, -50.0], [0.0, 100.0, -50.0]])
    tr = traverse(WORLD, pts, [1.0, 2.0, 1.0], 0.0, 1000.0)
    assert tr.nodes.shape == (4, 3)
    for s, where, t in ((50.0, [50.0, 0.0, -50.0], 50.0), (150.0, [100.0, 50.0, -50.0], 125.0),
                        (300.0, [0.0, 100.0, -50.0], 250.0), (250.0, [50.0, 100.0, -50.0], 200.0)):
        pos, at_t, leg = tr.at(s)
        assert pos.tolist() == pytest.approx(where) and at_t == pytest.approx(t), s


def test_return_route_computes_what_it_is_not_given_and_never_retraces_past_the_start() -> None:
    """Without ``free_from`` the return route finds the vertex that sees the recovery point itself; when only a
    vertex not yet flown sees it, there is no return route (None)."""
    from auvplan.endurance.pnr import return_route
    from auvplan.world import Margins, Terrain

    x = np.arange(-1000.0, 2001.0, 500.0)
    z = np.where(x == 500.0, -55.1, -100.0)[None, :].repeat(3, axis=0)
    world = World(Bounds(-1000, 2000, -1000, 1000, -200, 0), Terrain(x, np.array([-1000.0, 0.0, 1000.0]), z),
                  margins=Margins(min_altitude=5.0))
    pts = np.array([[1000.0, 0.0, -50.0], [1000.0, 0.0, -60.0], [1000.0, 300.0, -60.0]])
    pos = np.array([1000.0, 0.0, -55.0])
    rally = np.array([0.0, 0.0, -50.0])
    back = return_route(world, pts, pos, 0, rally)
    assert back is not None and back.tolist() == [pos.tolist(), pts[0].tolist(), rally.tolist()]
    assert return_route(world, pts, pos, 0, rally, np.array([False, False, True])) is None


def test_point_of_no_return_reports_its_point_home_and_verdict() -> None:
    """Still water, 1 km legs: with a large battery the vehicle can turn back anywhere (whole mission, at the
    end point, its home the start, named); a rally point 1 km from the start that costs 0.5 Wh more than the
    budget to reach is INFEASIBLE from the start (at the start); a flight the current blocks at 370 m stays
    within reach up to there (not the whole mission); the way back from the recovery point itself costs 0."""
    from auvplan._types import Status
    from auvplan.endurance.pnr import _return_energy, point_of_no_return
    from auvplan.endurance.power import EnergyModel

    pts = np.array([[10.0, 20.0, -30.0], [710.0, 20.0, -30.0], [710.0, 520.0, -80.0]])
    tr = traverse(WORLD, pts, 1.0, 0.0, 100.0)
    whole = point_of_no_return(WORLD, tr, EnergyModel(battery_wh=1e4))
    assert whole.status is Status.EXACT and whole.whole_mission and whole.leg == 1
    assert whole.position == pytest.approx((710.0, 520.0, -80.0)) and whole.recovery == (10.0, 20.0, -30.0)
    assert whole.s_m == pytest.approx(700.0 + np.hypot(500.0, 50.0))
    assert whole.message == "home (the start) stays within reach with the reserve from every point of the mission"
    rally = [10.0, -980.0, -30.0]
    e_ret0 = float(EnergyModel().power(1.0)) * 1000.0 / 3600.0
    none = point_of_no_return(WORLD, tr, EnergyModel(battery_wh=(e_ret0 - 0.5) / 0.7), recovery=rally)
    assert none.status is Status.INFEASIBLE and none.s_m == 0.0 and none.position == pytest.approx(tuple(pts[0]))
    assert none.message.startswith("the vehicle cannot reach the rally point [10.0, -980.0, -30.0] with its reserve")
    route = np.array([[0.0, 0.0, -50.0], [1000.0, 0.0, -50.0]])
    blocked = point_of_no_return(_blocked_world(), traverse(_blocked_world(), route, 1.0, 0.0, 10.0),
                                 EnergyModel(battery_wh=1e4))
    assert blocked.status is Status.EXACT and not blocked.whole_mission and blocked.s_m == pytest.approx(370.0)
    assert blocked.message.endswith("stays within reach up to where the current blocks the mission")
    free_from = np.ones(3, dtype=bool)
    assert _return_energy(WORLD, tr, EnergyModel(), 0.0, pts[0], 1.0, free_from, 100.0)[1] == 0.0


def test_a_leg_ending_a_rounding_under_the_reserve_does_not_enter_it() -> None:
    """As above, the second leg ending 1e-10 of the battery under the reserve (within the 1e-9 tolerance): it
    does not enter the reserve, the third does."""
    from auvplan.endurance.budget import budget_of
    from auvplan.endurance.power import EnergyModel

    pts = np.array([[0.0, 0.0, -50.0], [1000.0, 0.0, -50.0], [2000.0, 0.0, -50.0], [3000.0, 0.0, -50.0]])
    tr = traverse(WORLD, pts, 1.0, 0.0, 100.0)
    two = float(budget_of(tr, EnergyModel()).cumulative_wh[1])
    battery = two / (0.7 + 1e-10)  # usable - two = reserve - 1e-10 battery
    b = budget_of(tr, EnergyModel(battery_wh=battery))
    assert b.remaining_wh[1] - b.model.reserve_wh == pytest.approx(-1e-10 * battery, rel=1e-3)
    assert "the reserve is entered on leg 2" in b.message, b.message
