"""Hostile input, round 17, ``auvplan serve``: a survey file inside the served folder that is a FIFO (the survey's
long work blocked for ever: every later long request answered 'busy') or an OGR VRT reading a file outside the
served folders; a value set through the page of 10⁶ numbers (the scenario's lock held 14.5 s) or nested 800
deep (a bare 'RecursionError').  Each answered 400 at once naming the file or the key; the mission unchanged.
"""

from __future__ import annotations

import os
import threading

import numpy as np
import pytest

pytest.importorskip("starlette")
from starlette.testclient import TestClient  # noqa: E402

from auvplan.cli.serve import make_session  # noqa: E402
from auvplan.serve.app import LOCAL_HOSTS, make_app  # noqa: E402


@pytest.fixture(scope="module")
def served(tmp_path_factory):
    root = tmp_path_factory.mktemp("served17")
    os.mkfifo(root / "area.geojson")
    (root / "v.geojson").write_text("<OGRVRTDataSource><OGRVRTLayer name='passwd'><SrcDataSource>CSV:/etc/passwd"
                                    "</SrcDataSource></OGRVRTLayer></OGRVRTDataSource>", encoding="utf-8")
    session = make_session("dynamic-terrain", [str(root)])
    return session, TestClient(make_app(session, (*LOCAL_HOSTS, "testserver")))


def _post(client, path, body, timeout=30.0):
    """The answer to one request, or a failure when it has not come within ``timeout`` (the FIFO hung for ever)."""
    got = {}
    worker = threading.Thread(target=lambda: got.setdefault("r", client.post(path, json=body)), daemon=True)
    worker.start()
    worker.join(timeout)
    assert "r" in got, f"{path} {str(body)[:60]}: no answer within {timeout} s"
    return got["r"]


@pytest.mark.parametrize(("name", "needle"), [
    ("area.geojson", "is a FIFO, not a file of features"),
    ("v.geojson", "is an OGR VRT (it names other files or servers to read)"),
])
def test_a_survey_file_that_is_not_data_is_400_at_once(served, name, needle):
    session, client = served
    before = session.waypoints.copy()
    r = _post(client, "/api/survey", {"file": name})
    assert r.status_code == 400, r.text
    assert f"[survey] file = '{session.roots.resolve(name)}': {needle}" in r.json()["error"]
    np.testing.assert_array_equal(session.waypoints, before)
    assert session._long.acquire(blocking=False)  # the long work is free again: the next survey is not 'busy'
    session._long.release()


@pytest.mark.parametrize(("key", "value", "needle"), [
    ("start", [0.0] * 200_000, "[mission] start: a value over 10,000 items"),
    ("x", [[[[[[[[[[[[[[[[[[[]]]]]]]]]]]]]]]]]]], "[mission] x: a value nested over 16 deep"),
    ("name", "x" * 20_000, "[mission] name: a string of 20,000 characters, over 10,000"),
])
def test_a_value_too_large_for_any_key_is_400_naming_it(served, key, value, needle):
    session, client = served
    before = session.waypoints.copy()
    r = _post(client, "/api/set", {"table": "mission", "key": key, "value": value})
    assert r.status_code == 400, r.text
    assert r.json()["error"] == f"auvplan: error: {needle}; no scenario key takes one" or needle in r.json()["error"]
    np.testing.assert_array_equal(session.waypoints, before)


def test_a_value_at_the_bounds_reaches_the_loader():
    from auvplan.serve.actions.scenario import MAX_VALUE_DEPTH, MAX_VALUE_ITEMS, _check_value

    _check_value("mission", "start", [0.0] * (MAX_VALUE_ITEMS - 1))  # the list and its items: the bound itself
    deep: list = []
    for _ in range(MAX_VALUE_DEPTH):
        deep = [deep]
    _check_value("mission", "x", deep)
