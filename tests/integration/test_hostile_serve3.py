"""Issue #48, ``auvplan serve``: one request never freezes the page.

Hostile requests through the ASGI app (every one answered 400/409/503 naming the waypoint, key or value,
the mission unchanged), the long work run aside (a second long request answered ``busy`` at once, an
edit meanwhile wins and the long work's result is dropped, the state answered while it runs — with a real
uvicorn server on 127.0.0.1), the body size checked while it streams, the production ``Host`` list, the
files a served scenario names confined to the served folders, and a client dropping mid-body leaving no
traceback.  The latency and memory figures are ``benchmarks/serve_hostile.py``'s (not timed here).
"""

from __future__ import annotations

import json
import logging
import socket
import threading
import tomllib

import numpy as np
import pytest

pytest.importorskip("starlette")
pytest.importorskip("uvicorn")
import httpx  # noqa: E402
from starlette.testclient import TestClient  # noqa: E402

from auvplan.app.page.tomlout import dumps  # noqa: E402
from auvplan.cli.serve import make_session  # noqa: E402
from auvplan.serve.actions import planning as planning_mod  # noqa: E402
from auvplan.serve.app import LOCAL_HOSTS, MAX_BODY_BYTES, make_app  # noqa: E402
from serve_helpers import running  # noqa: E402

TEST_HOSTS = (*LOCAL_HOSTS, "testserver")


@pytest.fixture(scope="module")
def served(tmp_path_factory):
    root = tmp_path_factory.mktemp("served3")
    session = make_session("showcase", [str(root)])
    return session, TestClient(make_app(session, TEST_HOSTS)), root


def _unchanged(session, before):
    np.testing.assert_array_equal(session.waypoints, before)


# ---------------------------------------------------------------- edits: positions, indices, numbers
_BAD_XY = [1e9, -1e9, 1e300, 2e5, -2e5, "1e9", "nan", "inf", "-inf", "abc", "", [1, 2], {"a": 1}, True, False]


@pytest.mark.parametrize("op", ["move", "insert"])
@pytest.mark.parametrize("bad", _BAD_XY, ids=[repr(b)[:12] for b in _BAD_XY])
def test_an_edit_outside_the_area_or_not_a_number_is_400_naming_it(served, op, bad):
    session, client, _ = served
    before = session.waypoints.copy()
    r = client.post("/api/edit", json={"op": op, "index": 1, "x": bad, "y": float(before[1, 1])})
    assert r.status_code == 400, r.text
    err = r.json()["error"]
    assert err.startswith("auvplan: error: ") and f"{op}" in err
    assert ("outside the scenario's area" in err and ("waypoint 1" in err or "inserted waypoint" in err)
            and " x = " in err) or "not a number" in err or "finite" in err or "out of range" in err, err
    _unchanged(session, before)


_BAD_Z = [1e9, -1e9, 1e12, "nan", "x", [0], None]


@pytest.mark.parametrize("bad", _BAD_Z, ids=[repr(b)[:12] for b in _BAD_Z])
def test_a_typed_depth_outside_the_water_column_is_400_naming_the_waypoint(served, bad):
    session, client, _ = served
    before = session.waypoints.copy()
    r = client.post("/api/edit", json={"op": "depth", "index": 2, "z": bad})
    assert r.status_code == 400, r.text
    err = r.json()["error"]
    assert "waypoint 2 z = " in err or "not a number" in err or "finite" in err or "z is needed" in err, err
    _unchanged(session, before)


_BAD_INDEX = [-1, 10**9, 2**70, "0", 1.0, 1.5, True, None, [0], {"i": 0}]


@pytest.mark.parametrize("op", ["move", "delete", "depth"])
@pytest.mark.parametrize("bad", _BAD_INDEX, ids=[repr(b)[:12] for b in _BAD_INDEX])
def test_a_bad_waypoint_index_is_400_naming_it(served, op, bad):
    session, client, _ = served
    before = session.waypoints.copy()
    r = client.post("/api/edit", json={"op": op, "index": bad, "x": 0.0, "y": 0.0, "z": -100.0})
    assert r.status_code == 400 and "no such waypoint" in r.json()["error"], r.text
    assert repr(bad)[:8] in r.json()["error"]
    _unchanged(session, before)


@pytest.mark.parametrize("op", ["teleport", "", "MOVE", None, 3])
def test_an_unknown_edit_is_400_naming_it(served, op):
    session, client, _ = served
    before = session.waypoints.copy()
    r = client.post("/api/edit", json={"op": op, "index": 1, "x": 0.0, "y": 0.0})
    assert r.status_code == 400 and "edit op = " in r.json()["error"], r.text
    _unchanged(session, before)


def test_an_edit_inside_the_area_still_checks_and_shows_violations(served):
    """The bound is the area, not the check: a waypoint above the surface is accepted and shown as a violation."""
    session, client, _ = served
    r = client.post("/api/edit", json={"op": "depth", "index": 2, "z": 50.0})
    assert r.status_code == 200, r.text
    assert any(v["kind"] == "above_surface" for v in r.json()["check"]["violations"])
    assert client.post("/api/undo", json={}).status_code == 200


# ---------------------------------------------------------------- scenario keys through the page
_BAD_SET = [
    ("endurance", "ds_m", 1e-9, "ds_m = 1e-09"), ("endurance", "ds_m", 0, "ds_m = 0"),
    ("endurance", "ds_m", -5, "ds_m = -5"), ("endurance", "ds_m", 1e12, "ds_m = 1e+12"),
    ("endurance", "ds_m", "fine", "ds_m"), ("endurance", "deadline_s", -1, "deadline_s = -1"),
    ("endurance", "return_speed", -2, "return_speed = -2"), ("vehicle", "speed", 0, "speed"),
    ("vehicle", "speed", -1, "speed"), ("vehicle", "speed", "fast", "speed"),
    ("vehicle", "turn_radius_m", -3, "turn_radius_m"), ("vehicle", "max_depth_m", -10, "max_depth_m"),
    ("mission", "min_altitude_m", "low", "min_altitude_m"), ("mission", "start_time", "year 1", "start_time"),
    ("mission", "start_time", "0001-01-01T00:00:00Z", "start_time"),
    ("planner", "population", 10**9, "population"), ("planner", "iterations", -1, "iterations"),
    ("planner", "name", "nosuch", "name"), ("guidance", "name", "nosuch", "name"),
    ("avoidance", "name", "nosuch", "name"), ("vehicle", "nosuchkey", 1, "nosuchkey"),
    ("terrain", "file", "/etc/passwd", "[terrain]"), ("currents", "file", "../c.nc", "[currents]"),
    ("limits", "memory_mb", 1e9, "[limits]"), ("survey", "station_m", 1e-6, "[survey]"),
]


@pytest.mark.parametrize("table, key, value, named", _BAD_SET, ids=[f"{t}.{k}={v!r}"[:30] for t, k, v, _ in _BAD_SET])
def test_a_bad_setting_is_400_naming_the_key_and_nothing_changes(served, table, key, value, named):
    session, client, _ = served
    before, text = session.waypoints.copy(), session.text
    r = client.post("/api/set", json={"table": table, "key": key, "value": value})
    assert r.status_code == 400, r.text
    err = r.json()["error"]
    assert named in err and "Traceback" not in err, err
    assert session.text == text
    _unchanged(session, before)


# ---------------------------------------------------------------- survey areas and files from the page
_BAD_POLYGONS = [
    [[-1e9, -1e9], [1e9, -1e9], [1e9, 1e9]], [[0, 0], [1, 1]], [[0, 0], [0, 0], [0, 0]],
    [[0, 0], [1000, 1000], [1000, 0], [0, 1000]], [[0, "a"], [1, 1], [2, 0]], [[0, 0], [1e400, 1], [2, 0]],
    "square", None, [], [[[0, 0]]], [[0, 0, 0, 0]],
]


@pytest.mark.parametrize("poly", _BAD_POLYGONS, ids=[f"p{i}" for i in range(len(_BAD_POLYGONS))])
def test_a_bad_survey_area_is_400_and_the_mission_is_kept(served, poly):
    session, client, _ = served
    before = session.waypoints.copy()
    body = json.dumps({"polygon": poly}).replace("Infinity", "1e400")
    r = client.post("/api/survey", content=body, headers={"Content-Type": "application/json"})
    assert r.status_code == 400, r.text
    assert "survey" in r.json()["error"] or "polygon" in r.json()["error"] or "JSON" in r.json()["error"]
    _unchanged(session, before)


def test_scenario_files_outside_the_served_folders_are_refused(served, tmp_path_factory):
    """Opened scenarios name currents and tide files by relative path: confined like every page path."""
    session, client, root = served
    outside = tmp_path_factory.mktemp("elsewhere")
    (outside / "c.nc").write_bytes(b"CDF\x01")
    (outside / "tides.json").write_text("{}")
    link = root / "linked.nc"
    link.symlink_to(outside / "c.nc")
    cases = {
        "cur.toml": {"file": f"../{outside.name}/c.nc"},
        "abs.toml": {"file": str(outside / "c.nc")},
        "tide.toml": {"tides": f"../{outside.name}/tides.json"},
        "member.toml": {"uniform": [0.1, 0.0, 0.0], "members": [{"file": f"../{outside.name}/c.nc"}]},
        "link.toml": {"file": "linked.nc"},
    }
    opened = session.source
    for name, currents in cases.items():
        doc = {**tomllib.loads(session.text), "currents": currents}
        (root / name).write_text(dumps(doc), encoding="utf-8")
        r = client.post("/api/open", json={"scenario": name})
        assert r.status_code == 400, r.text
        err = r.json()["error"]
        assert "outside the served folders" in err and "[currents]" in err and name in err, err
    assert session.source == opened  # nothing was read, the open scenario stays


def test_a_zone_file_outside_the_served_folders_is_refused(served, tmp_path_factory):
    """A ``[[zones]] file`` is a data file the scenario names like its currents: confined too (it was read from
    anywhere: :func:`auvplan.io.scenario.specs.named_files` left it out)."""
    session, client, root = served
    outside = tmp_path_factory.mktemp("charts")
    (outside / "z.geojson").write_text('{"type": "FeatureCollection", "features": []}')
    opened = session.source
    doc = {**tomllib.loads(session.text), "zones": [{"name": "cable", "file": f"../{outside.name}/z.geojson"}]}
    (root / "zonefile.toml").write_text(dumps(doc), encoding="utf-8")
    r = client.post("/api/open", json={"scenario": "zonefile.toml"})
    assert r.status_code == 400, r.text
    err = r.json()["error"]
    assert "outside the served folders" in err and "[[zones]] #1 file" in err and "zonefile.toml" in err, err
    assert session.source == opened


# ---------------------------------------------------------------- the request itself
_BAD_BODIES = [
    ("text/plain", b'{"op": "move"}', "must be JSON"), ("", b"{}", "must be JSON"),
    ("application/json", b"{", "not JSON"), ("application/json", b"[1, 2]", "JSON object"),
    ("application/json", b'"x"', "JSON object"), ("application/json", b"[" * 100_000 + b"]" * 100_000, "not JSON"),
    ("application/json", b"\xff\xfe", "not JSON"), ("application/json", b" " * (MAX_BODY_BYTES + 1), "over the"),
]


@pytest.mark.parametrize("ctype, body, named", _BAD_BODIES, ids=[f"b{i}" for i in range(len(_BAD_BODIES))])
def test_a_bad_request_body_is_400_naming_why(served, ctype, body, named):
    _, client, _ = served
    r = client.post("/api/edit", content=body, headers={"Content-Type": ctype} if ctype else {})
    assert r.status_code == 400 and named in r.json()["error"], r.text


def test_a_body_over_the_limit_is_refused_while_it_streams(served):
    """No Content-Length (chunked): refused after the first chunk past the limit, not read whole."""
    _, client, _ = served
    sent = []

    def chunks():
        for _ in range(64):  # 64 × 1 MiB offered; the server stops reading after ~4 MiB
            sent.append(1)
            yield b" " * (1024 * 1024)

    r = client.post("/api/edit", content=chunks(), headers={"Content-Type": "application/json"})
    assert r.status_code == 400 and "over the" in r.json()["error"], r.text
    r = client.post("/api/edit", content=b"{}", headers={"Content-Type": "application/json",
                                                           "Content-Length": str(300 * 1024 * 1024)})
    assert r.status_code == 400 and "314,572,800 bytes" in r.json()["error"]


@pytest.mark.parametrize("host, allowed", [("testserver", False), ("evil.example", False), ("127.0.0.1", True),
                                           ("localhost", True), ("127.0.0.1.nip.io", False), ("", False)])
def test_the_production_host_list_has_no_test_names(served, host, allowed):
    session = served[0]
    client = TestClient(make_app(session), base_url=f"http://{host or 'x'}")
    r = client.get("/api/state", headers={"Host": host})
    assert (r.status_code == 200) == allowed, (host, r.status_code)


# ---------------------------------------------------------------- long work aside, never a frozen page
def test_long_work_runs_aside_busy_then_superseded_by_an_edit(monkeypatch, tmp_path):
    """A re-plan held in progress (an event holds it): the state answers, a second long request is 503 busy at
    once, an edit is applied, and the re-plan's result is then dropped (409 superseded) — over real HTTP."""
    session = make_session("showcase", [str(tmp_path)])
    started, release = threading.Event(), threading.Event()

    def held(world, mission, name, seed, progress=None):  # a re-plan that finishes when the test says
        started.set()
        assert release.wait(120)
        return None, session.waypoints[::-1].copy()

    monkeypatch.setattr(planning_mod, "replanned", held)
    with running(make_app(session)) as url, httpx.Client(base_url=url, timeout=120) as c:
        out: dict[str, httpx.Response] = {}
        t = threading.Thread(target=lambda: out.setdefault("plan", httpx.post(f"{url}/api/plan", json={},
                                                                              timeout=120)))
        t.start()
        assert started.wait(120)
        s = c.get("/api/state")  # answered while the re-plan runs (a lock held by it would hang here)
        assert s.status_code == 200 and not release.is_set()
        busy = c.post("/api/fly", json={})
        assert busy.status_code == 503 and busy.json()["busy"] and "a plan is running" in busy.json()["error"]
        w = np.asarray(s.json()["waypoints"])
        k = len(w) // 2
        e = c.post("/api/edit", json={"op": "move", "index": k, "x": w[k, 0] + 7.0, "y": w[k, 1]})
        assert e.status_code == 200 and not release.is_set()
        release.set()
        t.join(120)
        r = out["plan"]
        assert r.status_code == 409 and r.json()["superseded"], r.text
        assert session.waypoints[k, 0] == pytest.approx(w[k, 0] + 7.0)  # the edit stands
        assert c.post("/api/plan", json={}).status_code == 200  # the slot is free again (the held plan: released)


def test_a_client_dropping_mid_body_leaves_no_traceback(served):
    session = served[0]
    records: list[logging.LogRecord] = []

    class Keep(logging.Handler):
        def emit(self, record):
            records.append(record)

    handler = Keep(level=logging.DEBUG)
    try:
        with running(make_app(session)) as url:  # (uvicorn configures its loggers as it starts: handler after)
            for name in ("uvicorn.error", "uvicorn", "uvicorn.asgi"):
                logging.getLogger(name).addHandler(handler)
            host, port = url.removeprefix("http://").split(":")
            for _ in range(3):
                s = socket.create_connection((host, int(port)))
                s.sendall(b"POST /api/edit HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
                          b"Content-Length: 100000\r\n\r\n{\"op\": \"mo")
                s.close()
            assert httpx.get(f"{url}/api/state").status_code == 200  # and the server answers on
    finally:
        for name in ("uvicorn.error", "uvicorn", "uvicorn.asgi"):
            logging.getLogger(name).removeHandler(handler)
    assert not [r for r in records if r.exc_info or r.levelno >= logging.ERROR], [r.getMessage() for r in records]
