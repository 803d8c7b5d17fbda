"""mutants20: ``io/missions/parsed.py``'s memo (docs/mutants.md section 7).  Oracles: identity and call counts —
outside :func:`parse_once` nothing is kept; inside, one document at a time (a new text drops what was derived from
the last), an equal text is the same document, an exception is raised at every call, and a nested block has its own
memo and gives the outer one back."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.io.missions import parsed


def test_outside_the_block_every_call_computes():
    calls = []
    assert parsed.loads('{"v": 1}') is not parsed.loads('{"v": 1}')
    for _ in range(2):
        parsed.remembered("k", None, lambda: calls.append(1))
    assert len(calls) == 2


def test_one_document_at_a_time_and_an_equal_text_is_the_same_document():
    t1 = '{"v": 1}'
    with parsed.parse_once():
        a = parsed.loads(t1)
        assert parsed.loads("".join(['{"v"', ": 1}"])) is a  # equal, not the same str object
        assert parsed.remembered("k", a, lambda: "first") == "first"
        assert parsed.remembered("k", {"v": 1}, lambda: "other doc") == "other doc"  # kept by identity
        parsed.loads('{"v": 2}')  # another text: the memo is cleared
        assert parsed.remembered("k", a, lambda: "again") == "again"
        assert parsed.loads(t1) is not a


def test_an_exception_is_raised_at_every_call_and_never_kept():
    def boom():
        raise ValueError("no")

    with parsed.parse_once():
        doc = parsed.loads("[1]")
        for _ in range(2):
            with pytest.raises(ValueError):
                parsed.remembered("k", doc, boom)
        assert parsed.remembered("k", doc, lambda: 7) == 7 and parsed.remembered("k", doc, lambda: 8) == 7


def test_a_nested_block_has_its_own_memo_and_gives_the_outer_one_back():
    with parsed.parse_once():
        a = parsed.loads("[1]")
        with parsed.parse_once():
            assert parsed.loads("[1]") is not a
        assert parsed.loads("[1]") is a
    assert parsed.loads("[1]") is not a


def _mission(tmp_path, holds, current=0.5):
    import json

    from auvplan.io.data.geo import LocalFrame
    from auvplan.io.scenario import loader
    from helpers import HOLDS

    scen = tmp_path / "s.toml"
    scen.write_text(HOLDS + f"[currents]\nuniform = [0.0, {current}, 0.0]\n")
    world, mission = loader.build(loader.load(str(scen)))
    frame = LocalFrame(-7.0, 70.8)
    items = []
    for x, p1 in zip((500.0, 1500.0, 2500.0), holds):
        lon, lat = frame.inverse(x, 1000.0)
        items.append({"type": "SimpleItem", "command": 16, "frame": 3,
                      "params": [p1, 0, 0, None, float(lat), float(lon), -15.0]})
    lon, lat = frame.inverse(500.0, 1000.0)
    plan = tmp_path / "m.plan"
    plan.write_text(json.dumps({"mission": {"plannedHomePosition": [float(lat), float(lon), 0], "items": items}}))
    return world, mission, plan


def test_the_water_moved_through_in_each_hold_is_the_hold_times_the_current(tmp_path):
    """Uniform 0.5 m/s: holds of 0, 600 and 1 s (the least a .plan holds) at the three items (home first, no hold):
    0, 0, 300 and 0.5 m."""
    from auvplan.io.missions.energy import file_energy_flight

    world, mission, plan = _mission(tmp_path, [0, 600, 1])
    rec, ok, _line, moved, _ = file_energy_flight(world, mission, plan)
    assert ok and rec["energy_status"] == "EXACT" and len(rec["leg_speeds_mps"]) == 3
    np.testing.assert_allclose(moved, [0.0, 0.0, 300.0, 0.5], rtol=1e-9)
    assert file_energy_flight(world, mission, _mission(tmp_path, [0, 0, 0])[2])[3] is None  # no hold: None


def test_a_two_point_plan_is_flown(tmp_path):
    """Home above item 1 and one more item 1000 m east (no current): one leg of P(V) x 1000 / V; the vertical launch
    leg of 15 m first."""
    import json

    from auvplan.endurance import EnergyModel
    from auvplan.io.missions.energy import file_energy_flight

    world, mission, plan = _mission(tmp_path, [0, 0, 0], current=0.0)
    doc = json.loads(plan.read_text())
    doc["mission"]["items"] = doc["mission"]["items"][:1]  # home and one item: two waypoints, one 15 m leg
    plan.write_text(json.dumps(doc))
    rec, ok, _line, moved, _ = file_energy_flight(world, mission, plan)
    v = mission.vehicle.speed
    want = float(EnergyModel.from_vehicle(mission.vehicle).power(v)) * 15.0 / v / 3600.0
    assert ok and moved is None and rec["energy_wh"] == pytest.approx(want, rel=1e-6)
