"""fix20: ``mission check`` parses a file once.  Its readers (the waypoints three times, the speeds, the holds, the
datum and envelope, the tail-first legs, the terrain frame) each parsed a ``.plan``'s JSON and walked its items
again: six parses and six walks (a 10⁵-item ``.plan`` took 14 s, 6 s now at load 5).

Oracles: the count of parses and item walks of the file's own text (1 and 1, was 6 and 6); the records the check
writes with the memo off (every reader parsing for itself, as before) are the same, field for field."""

from __future__ import annotations

import contextlib
import json

from auvplan.app import check as app_check
from auvplan.io.data.geo import LocalFrame
from auvplan.io.missions import parsed
from auvplan.io.missions.readback import qgc_items
from helpers import HOLDS


def _plan(tmp_path) -> tuple[str, str]:
    scen = tmp_path / "s.toml"
    scen.write_text(HOLDS + "[currents]\nuniform = [0.0, 0.3, 0.0]\n")
    frame = LocalFrame(-7.0, 70.8)
    items = [{"type": "SimpleItem", "command": 178, "frame": 2, "params": [1, 1.2, -1, 0, 0, 0, 0]}]
    for x, p1 in zip((500.0, 1500.0, 2500.0), (0, 60, 30)):
        lon, lat = frame.inverse(x, 1000.0)
        items.append({"type": "SimpleItem", "command": 19 if p1 else 16, "frame": 3,
                      "params": [p1, 0, 0, None, float(lat), float(lon), -15.0]})
    lon, lat = frame.inverse(500.0, 1000.0)
    plan = tmp_path / "m.plan"
    plan.write_text(json.dumps({"mission": {"plannedHomePosition": [float(lat), float(lon), 0], "items": items}}))
    return str(scen), str(plan)


def test_a_plan_is_parsed_and_walked_once_with_the_same_records(tmp_path, monkeypatch):
    scen, plan = _plan(tmp_path)
    text = (tmp_path / "m.plan").read_text()
    counts = {"parse": 0, "walk": 0}
    loads, walk = json.loads, qgc_items._walk

    def counted_loads(s, *a, **k):
        counts["parse"] += s == text
        return loads(s, *a, **k)

    def counted_walk(doc):
        counts["walk"] += 1
        return walk(doc)

    monkeypatch.setattr(parsed.json, "loads", counted_loads)
    monkeypatch.setattr(qgc_items, "_walk", counted_walk)
    once = app_check.check_missions(scen, [plan], 15.0)[1][0]
    assert counts == {"parse": 1, "walk": 1}
    monkeypatch.setattr(parsed, "parse_once", contextlib.nullcontext)  # every reader for itself
    counts.update(parse=0, walk=0)
    each = app_check.check_missions(scen, [plan], 15.0)[1][0]
    assert counts["parse"] >= 6 and counts["walk"] >= 6
    assert json.dumps(once.record, sort_keys=True) == json.dumps(each.record, sort_keys=True)
    assert once.record["energy"]["leg_speeds_mps"] == [1.5, 1.2, 1.2]  # the launch dive: WPNAV_SPEED_DN


def test_an_edited_file_is_parsed_again(tmp_path):
    """The memo is keyed by the text: a file changed between two readers is never served stale."""
    with parsed.parse_once():
        a = parsed.loads('{"v": 1}')
        assert parsed.loads('{"v": 1}') is a and parsed.loads('{"v": 2}') == {"v": 2}
        assert parsed.remembered("k", a, lambda: 1) == 1 and parsed.remembered("k", a, lambda: 2) == 1
    assert parsed.loads('{"v": 1}') is not a  # nothing kept after the block
