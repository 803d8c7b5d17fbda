"""``auvplan serve`` sends the page only what an edit changed: the splice of the waypoints and of the
violations from the revision the page holds.  Oracle: a client that applies the splices holds exactly
the server's waypoints and violations after every edit."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from auvplan.serve.delta import changed_items, changed_slice

pytest.importorskip("starlette")
from starlette.testclient import TestClient  # noqa: E402

from auvplan.cli.serve import make_session  # noqa: E402
from auvplan.serve.app import make_app  # noqa: E402


def _splice(old, start, stop, items):
    return list(old[:start]) + list(items) + list(old[stop:])


def test_the_changed_slice_rebuilds_the_new_waypoints_and_is_the_smallest():
    rng = np.random.default_rng(7)
    for _ in range(300):
        old = rng.integers(0, 3, size=(int(rng.integers(2, 12)), 3)).astype(float)  # repeats: ties on purpose
        i = int(rng.integers(0, old.shape[0] + 1))
        j = int(rng.integers(i, old.shape[0] + 1))
        new = np.concatenate([old[:i], rng.integers(0, 3, size=(int(rng.integers(0, 4)), 3)), old[j:]])
        start, stop_old, stop_new = changed_slice(old, new)
        rebuilt = _splice(old.tolist(), start, stop_old, new[start:stop_new].tolist())
        assert rebuilt == new.tolist()
        a, b = old.tolist(), new.tolist()
        prefix = next((q for q in range(min(len(a), len(b))) if a[q] != b[q]), min(len(a), len(b)))
        suffix = next((q for q in range(min(len(a), len(b)) - prefix) if a[-1 - q] != b[-1 - q]),
                      min(len(a), len(b)) - prefix)
        assert (start, stop_old, stop_new) == (prefix, len(a) - suffix, len(b) - suffix)  # the smallest splice
        s2, so2, sn2 = changed_items(old.tolist(), new.tolist())
        assert (s2, so2, sn2) == (start, stop_old, stop_new)  # lists and arrays agree


def test_a_move_sends_one_waypoint_and_the_page_copy_equals_the_server(tmp_path):
    session = make_session("showcase", [str(tmp_path)])
    client = TestClient(make_app(session), base_url="http://127.0.0.1")
    m = session.mission
    n = 1000
    w = np.linspace(m.start, m.goal, n)
    w[1:-1, 0] += np.where(np.arange(1, n - 1) % 2 == 0, 40.0, -40.0)
    w[1:-1, 2] = -2300.0
    session._apply(w, "test", "1 000 waypoints")
    st = client.get("/api/state").json()
    page_w, page_v, rev = st["waypoints"], st["check"]["violations"], st["rev"]
    rng = np.random.default_rng(11)
    t = session.world.terrain
    i, j = np.unravel_index(np.argmax(t.z), t.z.shape)
    summit = (float(t.x[j]), float(t.y[i]))
    ops = ["move", "move", "summit", "insert", "delete", "depth", "undo", "move", "undo", "undo"]
    for op in ops:
        k = int(rng.integers(1, len(page_w) - 1))
        x, y = np.asarray(page_w[k][:2]) + rng.normal(0.0, 50.0, 2)
        body = {"move": {"op": "move", "index": k, "x": x, "y": y},
                "summit": {"op": "move", "index": 500, "x": summit[0], "y": summit[1], "z": float(t.z.max()) - 20},
                "insert": {"op": "insert", "x": x, "y": y},
                "delete": {"op": "delete", "index": k},
                "depth": {"op": "depth", "index": k, "z": -2400.0}}.get(op, {})
        r = client.post("/api/undo" if op == "undo" else "/api/edit", json={**body, "rev": rev})
        assert r.status_code == 200, r.text
        st = r.json()
        assert "waypoints" not in st and st["rev"] == rev + 1  # a splice, not the whole mission
        d = st["delta"]
        if op in ("move", "summit", "depth"):
            assert len(d["waypoints"]) == 1  # one waypoint sent of 1 000
            assert len(json.dumps(st)) < 20_000  # not the ~150 kB of the whole state
        page_w = _splice(page_w, d["start"], d["stop"], d["waypoints"])
        v = d["violations"]
        page_v = _splice(page_v, v["start"], v["stop"], v["items"])
        rev = st["rev"]
        if op == "summit":  # the seamount's summit breaks the altitude rule on the moved waypoint's legs
            assert {v["leg"] for v in page_v if v["kind"] == "altitude"} == {499, 500}
        assert page_w == session.waypoints.tolist()  # the oracle: the server's mission, to the bit
        server_v = json.loads(json.dumps(session.result.violations, allow_nan=True))
        assert len(page_v) == len(server_v)
        for a, b in zip(page_v, server_v):
            assert {**a, "value": None} == {**b, "value": None}
            assert a["value"] == b["value"] or (a["value"] is None and math.isnan(b["value"]))
    # an edit made on a revision that is not the server's current one is refused, nothing changes
    before = session.waypoints.copy()
    r = client.post("/api/edit", json={"op": "depth", "index": 3, "z": -2350.0, "rev": rev - 1})
    assert r.status_code == 409 and r.json()["stale"] and "the mission changed" in r.json()["error"]
    np.testing.assert_array_equal(session.waypoints, before)
    # a page one revision behind gets the splice from its revision; two behind, the whole list again
    st = client.post("/api/check", json={"semantics": "held", "pitch": 15.0, "rev": rev - 1}).json()
    assert st["delta"]["base"] == rev - 1 and st["rev"] == rev
    st = client.post("/api/check", json={"semantics": "held", "pitch": 15.0, "rev": rev - 2}).json()
    assert st["waypoints"] == session.waypoints.tolist() and "delta" not in st
    # without a revision (scripts, the tests above): the whole state, as before
    st = client.post("/api/edit", json={"op": "depth", "index": 3, "z": -2360.0}).json()
    assert st["waypoints"] == session.waypoints.tolist()
    assert len(st["check"]["leg_altitude_m"]) == len(session.waypoints) - 1


def test_the_incremental_budget_equals_mission_budget_after_edits(tmp_path):
    """In a steady current the legs' flights are cached: the budget equals ``mission_budget`` flown whole
    (showcase: Lamb–Oseen vortices), and only the moved waypoint's two legs are flown again."""
    from auvplan.app.page.budget import IncrementalBudget, steady
    from auvplan.endurance import EnergyModel, mission_budget

    session = make_session("showcase", [str(tmp_path)])
    world, mission = session.world, session.mission
    assert steady(world.currents)
    model = EnergyModel.from_vehicle(mission.vehicle)
    inc = IncrementalBudget(world, model, mission.endurance.ds_m)
    rng = np.random.default_rng(5)
    w = session.waypoints.copy()
    _, computed = inc.run(w, mission.vehicle.speed)
    assert computed == len(w) - 1
    for _ in range(6):
        k = int(rng.integers(1, len(w) - 1))
        w[k, :2] += rng.normal(0.0, 400.0, 2)
        got, computed = inc.run(w, mission.vehicle.speed)
        assert computed == 2
        ref = mission_budget(world, w, model, mission.vehicle.speed, 0.0, mission.endurance.ds_m)
        assert got.status is ref.status and got.message == ref.message
        np.testing.assert_allclose(got.t_end, ref.t_end, rtol=1e-12)
        np.testing.assert_allclose(got.energy_leg_wh, ref.energy_leg_wh, rtol=1e-12)
        assert got.margin_wh == pytest.approx(ref.margin_wh, rel=1e-12)
