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

    pts = PTS[[0, 0, 1]]
    tr = traverse(WORLD, pts, 1.0, 0.0, 10.0, dwell=[60.0, 0.0, 0.0])
    b = budget_of(tr, EnergyModel())
    assert np.isnan(b.speed_ground[0]) and b.speed_ground[1] == pytest.approx(1.0)
    assert b.energy_leg_wh.tolist() == pytest.approx([15.0 * 60.0 / 3600.0, 20.82 * 100.0 / 3600.0])
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


def test_the_way_back_retraces_half_a_metre_to_the_vertex_that_sees_home() -> None:
    """A ridge at x = 500 m (crest 55.1 m deep, 5 m minimum altitude) that the level leg home -> (1000, 0) at
    50 m clears by 5.1 m; the route then dives at x = 1000.  Half a metre down the dive the straight line
    home passes the crest 4.85 m above it (blocked), so the way back retraces the 0.5 m to the vertex and
    flies home from there: 1000.5 m at 1 m/s, P(1) x 1000.5 s (not the straight 1000.0001 m)."""
    from auvplan.endurance.pnr import _return_energy
    from auvplan.endurance.power import EnergyModel
    from auvplan.world import Margins, Terrain

    x = np.arange(-1000.0, 2001.0, 500.0)
    z = np.where(x == 500.0, -55.1, -100.0)[None, :].repeat(3, axis=0)
    world = World(Bounds(-1000, 2000, -1000, 1000, -200, 0), Terrain(x, np.array([-1000.0, 0.0, 1000.0]), z),
                  margins=Margins(min_altitude=5.0))
    pts = np.array([[0.0, 0.0, -50.0], [1000.0, 0.0, -50.0], [1000.0, 0.0, -90.0]])
    assert world.path_free(pts) and not world.path_free(np.array([[1000.0, 0.0, -50.5], pts[0]]))
    tr = traverse(world, pts, 1.0, 0.0, 100.0)
    free_from = np.array([world.path_free(np.stack([q, pts[0]])) for q in pts])
    model = EnergyModel()
    e_out, e_ret, pos, t, leg = _return_energy(world, tr, model, 1000.5, pts[0], 1.0, free_from, 100.0)
    assert leg == 1 and pos.tolist() == pytest.approx([1000.0, 0.0, -50.5]) and t == pytest.approx(1000.5)
    assert e_out == pytest.approx(20.82 * 1000.5 / 3600.0, rel=1e-9)
    assert e_ret == pytest.approx(20.82 * 1000.5 / 3600.0, rel=1e-9)
