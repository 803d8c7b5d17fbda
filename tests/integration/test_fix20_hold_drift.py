"""fix20: a ``.plan``'s hold at depth in the navigation budget.  Holding the item against a current c for T seconds
keeps the vehicle still over the ground but moves it |c|·T through the water; without bottom lock the vehicle
dead-reckons on water track, whose error grows ``drift_pct_no_lock`` per metre through the water (docs/navigation.md).
``mission check`` left the hold out: an hour held mid-water in 0.5 m/s added nothing to the predicted error.

Oracle, by hand from the model's closed form σ = sqrt(σ_fix² + D²), reported error = confidence × σ: the home is a
GPS fix (σ_fix = 5 m), D = (horizontal metres flown through the water + |c|·T at each hold at depth) × 2 %,
confidence 2; with bottom lock (a seabed 20 m under the items, DVL range 30 m) a hold adds nothing (the DVL sees the
ground still).  nav22: a leg across the current c at through-water speed V moves L·V/sqrt(V² − c²) through the water
(its ground speed sqrt(V² − c²)); the launch, a 15 m dive held over home, c·15/sqrt(V² − c²)."""

from __future__ import annotations

import json
import math

import pytest

from auvplan.cli import main
from auvplan.io.data.geo import LocalFrame
from helpers import HOLDS

_NAV = """[navigation]
drift_pct = 0.3
drift_pct_no_lock = 2.0
dvl_range_m = 30.0
fix_error_m = 5.0
max_error_m = {max_error}
confidence = 2.0
fixes = "none"
[currents]
uniform = [0.0, 0.5, 0.0]
"""
_SEABED = """[terrain.synthetic]
kind = "ridge"
depth = 35.0
cell_m = 10.0
ridge_x = 2900.0
ridge_width = 20.0
height = 1.0
"""


def _check(tmp_path, capsys, holds, max_error=500.0, seabed=False):
    scen = tmp_path / "s.toml"
    scen.write_text(HOLDS + _NAV.format(max_error=max_error) + (_SEABED if seabed else ""))
    frame = LocalFrame(-7.0, 70.8)
    items = []
    for x, p1 in zip((500.0, 1500.0, 2500.0), holds):
        lon, lat = frame.inverse(x, 1000.0)
        items.append({"type": "SimpleItem", "command": 16, "frame": 3,
                      "params": [p1, 0, 0, None, float(lat), float(lon), -15.0]})
    lon, lat = frame.inverse(500.0, 1000.0)
    plan = tmp_path / "m.plan"
    plan.write_text(json.dumps({"mission": {"plannedHomePosition": [float(lat), float(lon), 0], "items": items}}))
    code = main(["mission", "check", str(plan), "--scenario", str(scen), "--json"])
    rec = json.loads(capsys.readouterr().out)
    _SPEEDS[:] = rec["energy"]["leg_speeds_mps"]
    return code, rec["navigation"]


_SPEEDS: list[float] = []  # the legs' through-water speeds of the last check


def _water(legs: int) -> float:
    """The launch and the first ``legs`` 1000 m legs across 0.5 m/s, through the water (module notes)."""
    v = _SPEEDS
    return 15.0 * 0.5 / math.sqrt(v[0] ** 2 - 0.25) + sum(1000.0 * v[k] / math.sqrt(v[k] ** 2 - 0.25)
                                                          for k in range(1, legs + 1))


def _error(flown_m: float, held_m: float = 0.0) -> float:
    return 2.0 * math.hypot(5.0, 0.02 * (flown_m + held_m))


def test_an_hour_held_mid_water_grows_the_error_by_the_water_it_moves_through(tmp_path, capsys):
    code, nav = _check(tmp_path, capsys, [0, 3600, 0])
    legs = [r["nav_error_m"] for r in nav["legs"]]  # leg 0 the launch (vertical), 1 and 2 of 1000 m
    assert code == 0 and len(legs) == 3
    assert legs[1] == pytest.approx(_error(_water(1)), abs=0.006)  # before the hold at waypoint 2
    assert legs[2] == pytest.approx(_error(_water(2), 0.5 * 3600.0), abs=0.006)  # 5.0 + 40·1.06 + 36 m


def test_a_hold_at_the_last_item_fails_when_its_drift_passes_the_budget(tmp_path, capsys):
    """2000 m flown (2 121 m through the water): 2 hypot(5, 42.4) = 85.5 m at the last item; 600 s held in 0.5 m/s:
    2 hypot(5, 48.4) = 97.6 m."""
    code, nav = _check(tmp_path, capsys, [0, 0, 600], max_error=90.0)
    assert code == 1 and not nav["ok"]
    assert nav["message"] == "waypoint 3: predicted error 97.6 m at the end of its hold exceeds max_error_m 90 m"
    assert nav["nav_error_max_m"] == pytest.approx(_error(_water(2), 300.0), abs=1e-3)
    code, nav = _check(tmp_path, capsys, [0, 0, 0], max_error=90.0)
    assert code == 0 and nav["ok"]


def test_with_bottom_lock_a_hold_adds_nothing(tmp_path, capsys):
    """The seabed 35 m deep, the items at 15 m: 20 m altitude within the DVL's 30 m: 0.3 % per metre flown over the
    ground; the launch's first 5 m (altitude 35 to 30 m) without lock: 2 % of a third of its water run."""
    _, nav = _check(tmp_path, capsys, [0, 3600, 3600], seabed=True)
    want = 2.0 * math.hypot(5.0, 0.003 * 2000.0 + 0.02 * (_water(0) / 3.0))
    assert nav["legs"][2]["nav_error_m"] == pytest.approx(want, abs=0.006) and nav["ok"]
    assert nav["nav_error_max_m"] == pytest.approx(want, abs=1e-3)
