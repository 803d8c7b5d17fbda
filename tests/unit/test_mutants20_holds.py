"""mutants20: what the session's tests left open in a hold on station at the last vertex (``Traverse.end_hold``), its
energy and verdict, the hold's drift without bottom lock and the launch band (docs/mutants.md section 7).

Oracles, by hand: a steady current along the track whose speed grows with x (c = 0.2 + x / 10 000 m/s), so the
last vertex's hold is at the current of that vertex and no other; a current growing in time (c = 1e-4 t m/s), so the
hold's samples are at the midpoints of its 16 equal parts; the energy P(V) × time flown + P(|c|) × time held; the
reserve entered in the flight or in the hold by choosing the battery between the two sums."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
import pytest

from auvplan._types import Status
from auvplan.endurance import EnergyModel
from auvplan.endurance.budget import HOLD_SAMPLES, WH, budget_of, traverse
from auvplan.guidance.mission.limits import LAUNCH_ABOVE_M, waypoint_limits
from auvplan.io.scenario import loader
from auvplan.nav.budget import hold_drift
from auvplan.nav.params import NavParams
from auvplan.world.currents.fields import CurrentField
from helpers import HOLDS


@dataclass(frozen=True)
class _Field(CurrentField):
    """``(a + b x + g t, 0, 0)`` m/s."""

    a: float = 0.0
    b: float = 0.0
    g: float = 0.0

    def velocity(self, points, t=0.0):
        p = np.asarray(points, dtype=float)
        out = np.zeros(p.shape)
        out[..., 0] = self.a + self.b * p[..., 0] + self.g * t
        return out

    @property
    def steady(self) -> bool:
        return self.g == 0.0

    @property
    def max_speed(self) -> float:
        return 1.0


@pytest.fixture(scope="module")
def world(tmp_path_factory):
    scen = tmp_path_factory.mktemp("m20") / "s.toml"
    goal = 'goal = [2500.0, 1000.0, -15.0]\n'
    scen.write_text(HOLDS.replace(goal, goal + 'min_depth_m = 5.0\n'))
    return loader.build(loader.load(str(scen)))[0]


ROUTE = np.array([[0.0, 1000.0, -15.0], [1000.0, 1000.0, -15.0], [2000.0, 1000.0, -15.0], [3000.0, 1000.0, -15.0]])


def _held(world, hold: float, field: _Field, at: int = 3):
    dwell = np.zeros(4)
    dwell[at] = hold
    return traverse(replace(world, currents=field), ROUTE, 1.5, 0.0, 50.0, None, dwell, dwell > 0)


def test_the_last_vertex_hold_is_a_node_at_its_end_at_the_current_of_that_vertex(world):
    tr = _held(world, 600.0, _Field(a=0.2, b=1e-4))
    flown = float(tr.times[-1] - tr.times[0])
    assert tr.ok and tr.end_hold == 600.0 and tr.duration == pytest.approx(flown + 600.0, abs=1e-9)
    np.testing.assert_allclose(tr.hold_water[-1], 0.5, rtol=1e-12)  # 0.2 + 3000 / 10 000, not vertex 2's 0.4
    assert not tr.hold_water[:-1].any()
    np.testing.assert_array_equal(tr.nodes[-1], ROUTE[-1])
    assert tr.node_t[-1] == pytest.approx(tr.times[-1] + 600.0) and tr.node_leg[-1] == 2
    assert tr.node_s[-1] == pytest.approx(3000.0)
    model = EnergyModel(max_speed=2.0)
    b = budget_of(tr, model)
    hold_wh = float(model.power(0.5)) * 600.0 / WH
    fly_wh = float(model.power(1.5)) * float(tr.times[-1] - tr.times[-2]) / WH
    assert b.energy_leg_wh[-1] == pytest.approx(fly_wh + hold_wh, rel=1e-9)
    assert b.energy_leg_wh.sum() == pytest.approx(b.cumulative_wh[-1], rel=1e-12)
    assert b.t_end[-1] == pytest.approx(tr.times[-1] + 600.0)
    short = _held(world, 0.5, _Field(a=0.2, b=1e-4))  # half a second held is a hold
    assert short.end_hold == 0.5 and short.duration == pytest.approx(flown + 0.5, abs=1e-9)
    assert short.node_t[-1] == pytest.approx(short.times[-1] + 0.5) and short.hold_water[-1, 0] == pytest.approx(0.5)


def test_the_hold_is_sampled_at_the_midpoints_of_its_parts(world):
    tr = _held(world, 1600.0, _Field(g=1e-4))
    t0 = float(tr.times[-1])
    want = 1e-4 * (t0 + (np.arange(HOLD_SAMPLES) + 0.5) * 1600.0 / HOLD_SAMPLES)
    np.testing.assert_allclose(tr.hold_water[-1], want, rtol=1e-12)


def test_a_zero_length_leg_has_no_ground_speed(world):
    route = np.vstack([ROUTE[:2], ROUTE[1:3]])  # waypoint 1 twice: leg 1 of no length
    b = budget_of(traverse(world, route, 1.5), EnergyModel())
    assert np.isnan(b.speed_ground[1]) and b.speed_ground[0] == pytest.approx(1.5)


@pytest.mark.parametrize("where", ["hold", "flight"])
def test_the_reserve_entered_in_the_last_hold_or_in_the_last_flight_is_named_so(world, where):
    """60 s held in 0.5 m/s: P(0.5) x 60 s = 0.26 Wh (under 1 Wh); the battery's budget (0.9 - 0.2) B put between
    the flight's and the flight + hold's energy (the hold), or between legs 1's and 2's cumulated energy (the
    flight)."""
    tr = _held(world, 60.0, _Field(a=0.2, b=1e-4))
    e = budget_of(tr, EnergyModel(max_speed=2.0))
    hold_wh = float(EnergyModel().power(0.5)) * 60.0 / WH
    assert 0.0 < hold_wh < 1.0
    flown = e.cumulative_wh[-1] - hold_wh
    need = flown + hold_wh / 2 if where == "hold" else (e.cumulative_wh[1] + flown) / 2
    b = budget_of(tr, EnergyModel(max_speed=2.0, battery_wh=need / 0.7))
    assert b.status is Status.RESERVE_BROKEN
    tail = "in the hold at the last item" if where == "hold" else "on leg 2"
    assert b.message.endswith(f"the reserve is entered {tail}")


def test_a_hold_at_exactly_the_dvl_range_keeps_bottom_lock():
    """lock_fraction's lock is altitude <= dvl_range_m: the hold's drift starts just above it."""
    nav = NavParams(drift_pct_no_lock=2.0, dvl_range_m=30.0)
    got = hold_drift([30.0, np.nextafter(30.0, 99.0), 40.0, 40.0], ("", "", "", "gps"), nav, [100.0] * 4)
    np.testing.assert_array_equal(got, [0.0, 2.0, 2.0, 0.0])
    assert not hold_drift([40.0], ("",), nav, None).any()


def test_a_home_not_launched_is_judged_without_a_launch_run(world):
    """launch=False: no run reported, no launch text, whatever the home's offset; a single launch point reads."""
    limits = waypoint_limits(world, [[500.0, 1000.0, 0.0], [600.0, 1000.0, -15.0]], launch=False)
    assert limits.outside_depth_band == (0,) and limits.launch_run_m == 0.0
    assert not any("launch point" in r for r in limits.reasons())
    alone = waypoint_limits(world, [[500.0, 1000.0, 0.0]], launch=True)
    assert alone.launch and alone.outside_depth_band == () and alone.launch_run_m == 0.0


def test_a_launch_exactly_launch_above_m_off_is_above_and_reports_no_run(world):
    edge = waypoint_limits(world, [[0.0, 1000.0, 0.0], [LAUNCH_ABOVE_M, 1000.0, -15.0]], launch=True)
    assert edge.launch and edge.outside_depth_band == () and edge.launch_run_m == 0.0
    off = waypoint_limits(world, [[500.0, 1000.0, 0.0], [500.0, 1000.0 + 2 * LAUNCH_ABOVE_M, -15.0]], launch=True)
    assert not off.launch and off.launch_run_m == pytest.approx(2 * LAUNCH_ABOVE_M)


def test_the_launch_text_goes_only_with_the_home(world):
    """A home 500 m off its item: its run is named with waypoint 0's depth, never with another waypoint's."""
    off = waypoint_limits(world, [[0.0, 1000.0, 0.0], [500.0, 1000.0, -15.0], [600.0, 1000.0, -2.0]], True)
    assert off.outside_depth_band == (0, 2) and off.launch_run_m == pytest.approx(500.0)
    assert "the launch point is 500.0 m from above waypoint 1" in off.reasons()[0]
    later = replace(off, outside_depth_band=(2,))  # as if the home were in the band: waypoint 2 first
    assert "launch point" not in " ".join(later.reasons())


def test_the_nav_budget_by_hand_with_a_usbl_start_and_a_fix_midway(world):
    """No seabed (no lock: 2 % per metre); USBL ship at (0, 0), 1 % of the slant range: σ0 = 0.01 hypot(1000, 15) at
    waypoint 0 (not at waypoint 1, nor a GPS fix's 5 m); a GPS fix at waypoint 1: leg 0 arrives at hypot(σ0, 20),
    the largest error of the mission (leg 1 arrives at hypot(5, 20))."""
    from auvplan.nav.budget import mission_budget
    from auvplan.nav.params import UsblParams

    nav = NavParams(drift_pct_no_lock=2.0, fix_error_m=5.0, confidence=2.0, usbl=UsblParams(0.0, 0.0, 1.0))
    s0 = 0.01 * math.hypot(1000.0, 15.0)
    b = mission_budget(world, ROUTE[:3], ("usbl", "gps", ""), nav, (0.0, 0.0))
    np.testing.assert_allclose(b.error_m, [2 * s0, 10.0, 2 * math.hypot(5.0, 20.0)], rtol=1e-9)
    np.testing.assert_allclose(b.leg_error_m, [2 * math.hypot(s0, 20.0), 2 * math.hypot(5.0, 20.0)], rtol=1e-9)
    assert b.max_error_m == pytest.approx(2 * math.hypot(s0, 20.0), rel=1e-9)
    b = mission_budget(world, ROUTE[:3], ("usbl", "", ""), nav, (0.0, 0.0))
    assert b.error_m[0] == pytest.approx(2 * s0, rel=1e-9)


def test_a_short_one_leg_budget_under_a_metre(world):
    """10 m at 2 % from a 0.1 m fix: 2 hypot(0.1, 0.2) = 0.447 m, one leg, its lock share 0 (no seabed)."""
    from auvplan.nav.budget import mission_budget

    nav = NavParams(drift_pct_no_lock=2.0, fix_error_m=0.1, confidence=2.0)
    b = mission_budget(world, [[0.0, 1000.0, -15.0], [10.0, 1000.0, -15.0]], ("gps", ""), nav)
    assert b.max_error_m == pytest.approx(2 * math.hypot(0.1, 0.2), rel=1e-9)
    np.testing.assert_array_equal(b.leg_lock, [0.0])
