"""``auvplan serve`` without a browser: the incremental check equals ``fly_check``, edits, the
confinement to the served folders, localhost by default, and the CLI's error lines."""

from __future__ import annotations

import os
import tomllib
from pathlib import Path

import numpy as np
import pytest

from auvplan import cli
from auvplan.guidance.mission.flycheck import fly_check

pytest.importorskip("starlette")
pytest.importorskip("uvicorn")
from starlette.testclient import TestClient  # noqa: E402

from auvplan.app.page.check import CheckSettings, IncrementalCheck  # noqa: E402
from auvplan.app.page.tomlout import dumps  # noqa: E402
from auvplan.cli.serve import DEFAULT_HOST, make_session, server_config  # noqa: E402
from auvplan.serve.app import make_app  # noqa: E402


@pytest.fixture(scope="module")
def served(tmp_path_factory):
    root = tmp_path_factory.mktemp("served")
    session = make_session("showcase", [str(root)])
    return session, TestClient(make_app(session), base_url="http://127.0.0.1"), root


@pytest.mark.parametrize("name", ["marcus-wake", "track-double"])
def test_incremental_check_equals_fly_check_after_random_edits(name, marcus):
    """Every edit re-checks only its legs, and the result is fly_check's, figure for figure (a real seabed;
    a scene of static obstacles)."""
    from auvplan.io.scenario import loader

    world, mission = marcus[1:] if name == "marcus-wake" else loader.build(loader.load(name))
    rng = np.random.default_rng(3)
    w = np.linspace(mission.start, mission.goal, 60)
    if world.terrain is not None:
        w[:, 2] = np.linspace(-1500.0, -1200.0, 60)
    step = 0.05 * (world.bounds.xmax - world.bounds.xmin)
    ic = IncrementalCheck(world, mission)
    hit = False
    for semantics in ("held", "ramp"):
        settings = CheckSettings(semantics, 15.0)
        ic.run(w, settings)
        for e in range(9):
            k = int(rng.integers(1, len(w) - 1))
            w = w.copy()
            w[k, :2] += rng.normal(0.0, step, 2)
            if e == 8 and world.obstacles:  # the last edit: onto an obstacle
                w[k] = world.obstacles[0].center
            r = ic.run(w, settings)
            if semantics == "ramp":
                assert r.rechecked == 2  # only the two legs of the moved waypoint
            oracle = fly_check(world, w, semantics, 15.0)
            assert r.check.as_dict() == oracle.as_dict()
            np.testing.assert_array_equal(r.check.leg_altitude_m, oracle.leg_altitude_m)
            bad = {v["leg"] for v in r.violations if v["kind"] == "altitude"}
            assert bad == set(np.flatnonzero(oracle.leg_altitude_m < oracle.required_altitude_m - 1e-6).tolist())
            hit |= oracle.obstacle_hits > 0
            assert len({v["leg"] for v in r.violations if v["kind"] == "obstacle"}) == oracle.obstacle_hits
    assert hit == bool(world.obstacles)  # the obstacle figures were exercised where there are obstacles


def test_scenario_documents_round_trip_through_the_toml_writer():
    from auvplan.io.scenario.builtins import builtin_scenarios, resolve

    for name in builtin_scenarios():
        doc = tomllib.loads(resolve(name).read_text(encoding="utf-8"))
        assert tomllib.loads(dumps(doc)) == doc, name


def test_the_page_and_its_assets_are_served_locally(served):
    _, client, _ = served
    page = client.get("/")
    assert page.status_code == 200 and "<div id=\"chart\">" in page.text
    assert "http" not in page.text.replace("http-equiv", "")  # no asset from the network
    js = client.get("/static/plotly.min.js")
    assert js.status_code == 200 and len(js.text) > 1_000_000
    assert client.get("/static/app.js").status_code == 200
    assert client.get("/static/..%2Fapp.py").status_code == 404
    assert client.get("/static/session.py").status_code == 404
    chart = client.get("/api/chart").json()
    assert any(t.get("name") == "seabed" for t in chart["data"])  # the report's chart


def test_edits_history_undo_and_candidates(served):
    session, client, _ = served
    st = client.get("/api/state").json()
    n = len(st["waypoints"])
    st = client.post("/api/edit", json={"op": "insert", "x": 40000.0, "y": 60000.0}).json()
    assert len(st["waypoints"]) == n + 1
    st = client.post("/api/edit", json={"op": "depth", "index": 1, "z": -2700.0}).json()
    assert st["waypoints"][1][2] == -2700.0
    np.testing.assert_array_equal(session.waypoints, np.array(st["waypoints"]))
    assert st["check"]["summary"]["min_altitude_m"] == pytest.approx(
        fly_check(session.world, session.waypoints).min_altitude_m)
    st = client.post("/api/keep", json={"name": "mine"}).json()
    assert st["candidates"][-1]["name"] == "mine"
    client.post("/api/undo", json={})
    st = client.post("/api/undo", json={}).json()
    assert len(st["waypoints"]) == n
    assert [h["op"] for h in st["history"]][-4:] == ["insert", "depth", "undo", "undo"]
    st = client.post("/api/choose", json={"index": len(st["candidates"]) - 1}).json()
    assert len(st["waypoints"]) == n + 1 and st["waypoints"][1][2] == -2700.0
    bad = client.post("/api/edit", json={"op": "move", "index": 99, "x": 0, "y": 0})
    assert bad.status_code == 400 and bad.json()["error"].startswith("auvplan: error: waypoint 99")
    bad = client.post("/api/edit", json={"op": "move", "index": 1, "x": "nan", "y": 0})
    assert bad.status_code == 400 and "finite" in bad.json()["error"]
    assert client.post("/api/edit", content=b"[1,").status_code == 400


def test_settings_are_validated_exactly_as_the_cli_does(served, tmp_path, capsys):
    session, client, _ = served
    r = client.post("/api/set", json={"table": "vehicle", "key": "speed", "value": -1})
    assert r.status_code == 400
    # the same document through the command line: the same error line
    doc = tomllib.loads(session.text)
    doc["vehicle"]["speed"] = -1
    bad = Path(session.source)  # the messages name the scenario's file
    text = dumps(doc)
    scenario = tmp_path / bad.name
    scenario.write_text(text, encoding="utf-8")
    capsys.readouterr()
    assert cli.main(["validate", str(scenario)]) == 2
    line = capsys.readouterr().err.strip()
    assert r.json()["error"] == line.replace(str(scenario), session.source)
    r = client.post("/api/set", json={"table": "vehicle", "key": "no_such_key", "value": 1})
    assert r.status_code == 400 and "no_such_key" in r.json()["error"]
    assert client.post("/api/set", json={"table": "terrain", "key": "file", "value": "/etc/passwd"}).status_code == 400
    r = client.post("/api/set", json={"table": "vehicle", "key": "max_pitch_deg", "value": 2.0}).json()
    assert not r["check"]["summary"]["vehicle_ok"]
    assert any(v["kind"] == "max_pitch_deg" for v in r["check"]["violations"])
    client.post("/api/set", json={"table": "vehicle", "key": "max_pitch_deg", "value": None})


def test_paths_outside_the_served_folders_are_refused(served, tmp_path_factory):
    session, client, root = served
    outside = tmp_path_factory.mktemp("outside")
    (outside / "secret.toml").write_text("name = 'x'\n", encoding="utf-8")
    (outside / "area.geojson").write_text("{}", encoding="utf-8")
    link = root / "link.toml"
    if not link.exists():
        os.symlink(outside / "secret.toml", link)
    for name in ("../secret.toml", str(outside / "secret.toml"), "/etc/passwd", "link.toml",
                 f"sub/../../{outside.name}/secret.toml", "..\\secret.toml"):
        r = client.post("/api/open", json={"scenario": name})
        assert r.status_code == 400, name
        assert "outside the served folders" in r.json()["error"] or "'..' is not allowed" in r.json()["error"]
    r = client.post("/api/survey", json={"file": str(outside / "area.geojson")})
    assert r.status_code == 400 and "outside the served folders" in r.json()["error"]
    for name in ("../evil", "/tmp/evil", "a/b", ".hidden", ""):
        assert client.post("/api/save", json={"name": name}).status_code == 400, name
    assert not (root.parent / "evil").exists()
    assert session.sc.name == "showcase"  # nothing was opened


def test_binds_to_localhost_by_default():
    args = cli._parser().parse_args(["serve", "--no-browser"])
    assert args.host == DEFAULT_HOST == "127.0.0.1" and args.port == 8765
    cfg = server_config(object())
    assert cfg.host == "127.0.0.1"


def test_a_live_server_listens_on_localhost_only(served):
    from serve_helpers import running

    session, _, _ = served
    import httpx

    with running(make_app(session)) as url:
        assert url.startswith("http://127.0.0.1:")
        assert httpx.get(url + "/api/state").status_code == 200


def test_saving_never_overwrites(served):
    session, client, root = served
    (root / "taken").mkdir()
    (root / "taken" / "notes.txt").write_text("mine", encoding="utf-8")
    r = client.post("/api/save", json={"name": "taken"})
    assert r.status_code == 400 and "never overwritten" in r.json()["error"]
    assert (root / "taken" / "notes.txt").read_text(encoding="utf-8") == "mine"


def test_replan_fly_and_compare_candidates(tmp_path):
    session = make_session("track-single", [str(tmp_path)])
    client = TestClient(make_app(session), base_url="http://127.0.0.1")
    first = client.post("/api/keep", json={"name": "as opened"}).json()
    st = client.post("/api/plan", json={"planner": "grid", "seed": 0}).json()
    rows = st["candidates"]
    assert [r["name"] for r in rows] == ["as opened", "grid seed 0"]
    assert rows[1]["waypoints"] == len(st["waypoints"])
    # document 001's tracking scene: the route runs through the obstacles that local avoidance steers round,
    # so mission check fails it; the table says what an independent fly_check says
    oracle = fly_check(session.world, np.array(st["waypoints"]), "held")
    assert oracle.obstacle_hits > 0 and rows[1]["ok"] is False
    assert rows[1]["length_m"] == pytest.approx(np.linalg.norm(np.diff(st["waypoints"], axis=0), axis=1).sum())
    st = client.post("/api/fly", json={}).json()
    assert st["flight"]["status"] == "EXACT" and len(st["flight"]["x"]) > 10
    st = client.post("/api/choose", json={"index": 0}).json()
    assert st["waypoints"] == first["waypoints"] and st["flight"] is None  # the flight was of the other mission
    assert client.post("/api/plan", json={"planner": "no-such"}).status_code == 400
    assert client.post("/api/plan", json={"seed": -1}).status_code == 400


def test_a_saved_folder_reopens_with_the_same_mission_and_exports(served, capsys):
    session, client, root = served
    client.post("/api/edit", json={"op": "insert", "x": 39000.0, "y": 58500.0})
    saved = client.post("/api/save", json={"name": "reopen"}).json()
    out = Path(saved["result"]["saved"])
    assert out == root / "reopen" and (out / "history.json").is_file()
    again = make_session(str(out))
    np.testing.assert_array_equal(again.waypoints, session.waypoints)
    assert again.result.summary == pytest.approx(session.result.summary)
    capsys.readouterr()
    assert cli.main(["export", str(out), "--force"]) == 0
    assert cli.main(["mission", "check", "--scenario", str(out / "scenario.toml"), str(out / "mission.gpx"),
                     "--json"]) == 0


def test_import_a_survey_area_from_a_file_in_the_served_folder(tmp_path):
    import json

    from auvplan.io.data.geo import LocalFrame

    session = make_session("shelf-survey", [str(tmp_path)])
    frame = LocalFrame(*session.world.origin)
    x = np.array([64600.0, 66000.0, 66000.0, 64600.0, 64600.0])
    y = np.array([3400.0, 3400.0, 4600.0, 4600.0, 3400.0])
    lon, lat = frame.inverse(x, y)
    (tmp_path / "area.geojson").write_text(json.dumps({"type": "FeatureCollection", "features": [{
        "type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [
            np.column_stack([lon, lat]).tolist()]}}]}), encoding="utf-8")
    client = TestClient(make_app(session), base_url="http://127.0.0.1")
    st = client.post("/api/survey", json={"file": "area.geojson"}).json()
    area = np.array(st["survey_area"])
    assert area[:, 0].min() == pytest.approx(64600.0, abs=0.5) and area[:, 1].max() == pytest.approx(4600.0, abs=0.5)
    assert st["history"][-1]["op"] == "survey" and st["check"]["summary"]["check_ok"]
    r = client.post("/api/survey", json={"file": "missing.geojson"})
    assert r.status_code == 400 and "no such file in the served folders" in r.json()["error"]


def test_other_sites_cannot_drive_the_server(served):
    """A page elsewhere can only send 'simple' requests (text/plain) or reach 127.0.0.1 under its own
    DNS name: both are refused."""
    session, client, _ = served
    n = len(session.waypoints)
    r = client.post("/api/edit", content=b'{"op": "delete", "index": 1}', headers={"Content-Type": "text/plain"})
    assert r.status_code == 400 and "application/json" in r.json()["error"]
    r = client.get("/api/state", headers={"Host": "evil.example:8765"})
    assert r.status_code == 400
    assert len(session.waypoints) == n


def test_the_serve_command_binds_localhost_and_refuses_a_busy_port(monkeypatch, tmp_path, capsys):
    import socket
    import webbrowser

    import uvicorn

    seen = {}

    def fake_run(self, *a, **k):
        seen["host"], seen["port"] = self.config.host, self.config.port
        seen["app"] = self.config.app

    monkeypatch.setattr(uvicorn.Server, "run", fake_run)
    monkeypatch.setattr(webbrowser, "open", lambda url: seen.setdefault("opened", url))
    monkeypatch.chdir(tmp_path)
    assert cli.main(["serve", "track-single", "--no-browser", "--port", "0"]) == 0
    assert seen["host"] == "127.0.0.1" and "opened" not in seen
    client = TestClient(seen["app"], base_url="http://127.0.0.1")
    assert client.get("/api/state").json()["scenario"] == "track-single"
    with socket.create_server(("127.0.0.1", 0)) as busy:
        port = busy.getsockname()[1]
        capsys.readouterr()
        assert cli.main(["serve", "track-single", "--no-browser", "--port", str(port)]) == 2
        err = capsys.readouterr().err.strip()
        assert err.startswith(f"auvplan: error: --port {port}: cannot serve") and "\n" not in err
