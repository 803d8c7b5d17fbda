"""A surface fix's dwell in a head current is not a deadlock (audit of issue 52's simulated dwell).

At a GPS fix the closed loop drifts with the current for ``surface_s`` (propulsion off), so a head current carries
the vehicle back behind the leg it has just begun; regaining that is progress.  Oracle (closed form): the drift
back is ``surface_s · |c|``, regained at the ground speed ``V − |c|``, so the flight takes the planned time (the
fixes' timing through the current, which holds the dwell but not its drift) plus ``surface_s · |c| / (V − |c|)``,
less the arrival radius at the ground speed, after the launch's dive from the surface (60 m at ``sqrt(V² − |c|²)``,
flown since wave 18).
"""

from __future__ import annotations

import pytest

from auvplan._types import Status
from auvplan.io.scenario import loader
from auvplan.sim import run_mission

SCENARIO = """name = "dwell-regain"
[bounds]
x = [0.0, 6000.0]
y = [-1000.0, 1000.0]
z = [-1000.0, 0.0]
[currents]
uniform = [-0.7, 0.0, 0.0]
[mission]
start = [200.0, 0.0, -60.0]
goal = [5200.0, 0.0, -60.0]
route = [[200.0, 0.0, -60.0], [5200.0, 0.0, -60.0]]
min_depth_m = 0.0
[vehicle]
speed = 1.5
max_pitch_deg = 20.0
[navigation]
drift_pct_no_lock = 2.0
max_error_m = 250.0
confidence = 2.0
surface_s = 300.0
[avoidance]
name = "none"
[sim]
dt = 1.0
record_every = 20
"""


def test_a_dwell_drifted_back_by_a_head_current_is_regained_not_a_deadlock():
    """One fix (E = 250 m at 2 σ: the 5 km leg moves 9.4 km through the water against 0.7 m/s, 375 m without a
    fix; nav22: 130 m, one fix before the water distance, now takes three), 300 s adrift in 0.7 m/s against a
    1.5 m/s vehicle (210 m back, longer to regain than
    the default 120 s deadlock watch): it arrives, in the closed form's time to 5 s (before: DEADLOCK at 2917 s,
    'no progress along the route for 121 s')."""
    world, mission = loader.build(loader.loads(SCENARIO, "dwell-regain.toml"))
    assert mission.sim.deadlock_time < 300.0 * 0.7 / 0.8
    r = run_mission(world, mission)
    assert r.nav is not None and r.nav.kinds.count("gps") == 1
    assert r.sim is not None and r.sim.status is Status.EXACT, r.sim.events[-1]
    dive = 60.0 / (1.5**2 - 0.7**2) ** 0.5  # the launch from the surface above the start, held against 0.7 m/s
    expected = dive + r.nav.vertex_times_s[-1] + (300.0 * 0.7 - mission.sim.arrival_radius) / (1.5 - 0.7)
    assert r.sim.t[-1] == pytest.approx(expected, abs=5.0)  # 45 s of dive: rel=0.01 could not see it
