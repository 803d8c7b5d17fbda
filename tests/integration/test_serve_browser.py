"""``auvplan serve`` in headless Chromium (Playwright): drag a waypoint onto the seamount and see the
violation on its legs, drag it back and see OK; draw an area and get a survey; save, and
``auvplan mission check`` on the saved files agrees with the page.  The oracle of every figure the
page shows is an independent ``fly_check`` / ``mission check`` run on the same waypoints."""

from __future__ import annotations

import json

import numpy as np
import pytest

from auvplan import cli
from auvplan.cli.serve import make_session
from auvplan.guidance.mission.flycheck import fly_check
from serve_helpers import chromium, running

pytest.importorskip("starlette")
pytest.importorskip("uvicorn")
sync_api = pytest.importorskip("playwright.sync_api")


@pytest.fixture(scope="module")
def browser():
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=chromium(), args=["--no-sandbox"])
        yield b
        b.close()


def _page(browser, url):
    page = browser.new_page(viewport={"width": 1400, "height": 900})
    page.set_default_timeout(120_000)  # a safety net on a loaded machine (the waits end on a state), not an oracle
    errors, outside = [], []
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.on("request", lambda r: outside.append(r.url) if not r.url.startswith((url, "data:", "blob:")) else None)
    page.goto(url + "/")
    page.wait_for_selector("body[data-ready='1']", timeout=120_000)
    return page, errors, outside


def _drag(page, src, dst):
    a = page.evaluate("([x, y]) => window.auvplan.toPx(x, y)", list(src))
    b = page.evaluate("([x, y]) => window.auvplan.toPx(x, y)", list(dst))
    page.mouse.move(*a)
    page.mouse.down()
    for f in (0.3, 0.6, 1.0):
        page.mouse.move(a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]))
    page.mouse.up()
    page.wait_for_function("() => document.body.dataset.pending === '0'")


def test_drag_a_waypoint_onto_the_seamount_and_back(browser, tmp_path):
    session = make_session("showcase", [str(tmp_path)])
    from auvplan.serve.app import make_app

    world = session.world
    t = world.terrain
    i, j = np.unravel_index(np.argmax(t.z), t.z.shape)
    summit = (float(t.x[j]), float(t.y[i]))  # the shallowest seabed in the box: above every waypoint's depth
    with running(make_app(session)) as url:
        page, errors, outside = _page(browser, url)
        assert page.inner_text("#verdict") == "OK"
        w0 = np.array(page.evaluate("() => window.auvplan.waypoints()"))
        k = 2
        assert t.z.max() > w0[k, 2] + world.margins.min_altitude  # the summit is a collision at this depth
        _drag(page, w0[k, :2], summit)
        page.wait_for_selector(f"#violations li[data-leg='{k - 1}'][data-kind='altitude']")
        assert page.inner_text("#verdict") == "FAIL"
        w1 = np.array(page.evaluate("() => window.auvplan.waypoints()"))
        assert np.hypot(*(w1[k, :2] - summit)) < 0.02 * (world.bounds.xmax - world.bounds.xmin)  # moved there
        oracle = fly_check(world, w1, "held")
        for leg in (k - 1, k):
            shown = float(page.get_attribute(f"#violations li[data-leg='{leg}'][data-kind='altitude']", "data-value"))
            assert shown == pytest.approx(oracle.leg_altitude_m[leg], abs=1e-9)
            assert shown < 0  # into the seabed
            assert f"altitude {oracle.leg_altitude_m[leg]:.1f} m" in page.inner_text("#violations")
        marks = page.evaluate("() => { const d = document.getElementById('chart').data; "
                              "return d.find(t => t.name === 'violation at leg').text; }")
        assert marks == [f"leg {k - 1}", f"leg {k}"]  # marked on the map at those legs
        keys = page.evaluate("() => document.getElementById('chart').data.find(t => t.name === 'key waypoints').x")
        np.testing.assert_allclose(keys, session.keys[:, 0])  # the key waypoints of the edited mission
        assert float(page.get_attribute("#min-alt", "data-value")) == pytest.approx(oracle.min_altitude_m, abs=1e-9)
        _drag(page, w1[k, :2], w0[k, :2])
        page.wait_for_selector("#verdict.ok")
        assert page.locator("#violations li").count() == 0
        w2 = np.array(page.evaluate("() => window.auvplan.waypoints()"))
        assert fly_check(world, w2, "held").ok
        assert [h["op"] for h in session.history] == ["open", "move", "move"]
        assert not errors, errors
        assert not outside, outside  # every asset from the server: works offline


def test_save_then_mission_check_agrees_with_the_page(browser, tmp_path, capsys):
    session = make_session("showcase", [str(tmp_path)])
    from auvplan.serve.app import make_app

    with running(make_app(session)) as url:
        page, errors, _ = _page(browser, url)
        w0 = np.array(page.evaluate("() => window.auvplan.waypoints()"))
        mid = 0.5 * (w0[1, :2] + w0[2, :2]) + np.array([300.0, -300.0])
        page.click("button[data-mode='add']")
        page.mouse.click(*page.evaluate("([x, y]) => window.auvplan.toPx(x, y)", list(mid)))
        page.wait_for_function(f"() => window.auvplan.waypoints().length === {len(w0) + 1}")
        page.fill("#save-name", "chosen")
        page.click("#save")
        page.wait_for_selector("#saved:has-text('saved in')")
        min_alt = float(page.get_attribute("#min-alt", "data-value"))
        energy = float(page.get_attribute("#energy", "data-value"))
        assert not errors, errors
        # pan the chart: the report's chart underneath follows the editable overlay, to the metre
        ranges = "() => ['chart', 'base'].map(id => { const f = document.getElementById(id)._fullLayout; " \
                 "return [f.xaxis.range, f.yaxis.range, f.xaxis._offset, f.yaxis._offset]; })"
        before = page.evaluate(ranges)
        page.click("button[data-mode='pan']")
        box = page.locator("#chart").bounding_box()
        page.mouse.move(box["x"] + 300, box["y"] + 300)
        page.mouse.down()
        page.mouse.move(box["x"] + 400, box["y"] + 350, steps=4)
        page.mouse.up()
        # the chart follows asynchronously (two relayouts): wait for the state, not for a fixed pause
        try:
            page.wait_for_function(f"() => {{ const [o, c] = ({ranges})(); return o[0][0] !== {before[0][0][0]!r} "
                                   "&& [0, 1].every(k => [0, 1].every(j => Math.abs(o[k][j] - c[k][j]) <= 1.0)) && "
                                   "[2, 3].every(k => Math.abs(o[k] - c[k]) <= 0.5); }", timeout=120_000)
        except sync_api.TimeoutError:
            pass  # the assertions below name what did not follow
        overlay, chart = page.evaluate(ranges)
        assert overlay[0] != before[0][0]  # it moved
        np.testing.assert_allclose(overlay[0], chart[0], atol=1.0)
        np.testing.assert_allclose(overlay[1], chart[1], atol=1.0)
        assert overlay[2:] == pytest.approx(chart[2:], abs=0.5)  # the same plot area on the page
    out = tmp_path / "chosen"
    capsys.readouterr()
    code = cli.main(["mission", "check", "--scenario", str(out / "scenario.toml"), str(out / "mission.moos"),
                     "--json"])
    rec = json.loads(capsys.readouterr().out)
    assert code == 0 and rec["ok"]
    assert rec["min_altitude_m"] == pytest.approx(min_alt, abs=0.01)  # exports round to 1 mm
    assert rec["energy"]["energy_wh"] == pytest.approx(energy, rel=1e-3)
    assert rec["legs"] == len(w0)  # the inserted waypoint is in the saved mission


def test_draw_an_area_and_get_a_survey(browser, tmp_path):
    session = make_session("shelf-survey", [str(tmp_path)])
    from auvplan.serve.app import make_app

    corners = [(64500.0, 3300.0), (66500.0, 3300.0), (66500.0, 4700.0), (64500.0, 4700.0)]
    with running(make_app(session)) as url:
        page, errors, _ = _page(browser, url)
        page.click("button[data-mode='draw']")
        for c in corners:
            page.mouse.click(*page.evaluate("([x, y]) => window.auvplan.toPx(x, y)", list(c)))
        page.click("#finish-area")
        page.wait_for_selector("#history li:has-text('survey of a drawn area')", state="attached", timeout=120_000)
        area = np.array(session.survey_area)
        w = np.array(page.evaluate("() => window.auvplan.waypoints()"))
        assert not errors, errors
    # the drawn corners became the survey area (to the pixel the clicks landed on)
    assert area[:-1, 0].min() == pytest.approx(64500.0, abs=30) and area[:-1, 0].max() == pytest.approx(66500.0, abs=30)
    assert session.sc.survey.polygon_xy and len(session.sc.survey.polygon_xy) == 4
    import shapely

    poly = shapely.Polygon(area)
    inside = shapely.contains_xy(poly.buffer(1.0), w[:, 0], w[:, 1])
    assert inside.sum() > 20  # survey lines over the area
    assert np.hypot(*(w[0, :2] - np.array(session.mission.start[:2]))) < 1.0  # from the launch point
    assert session.result.summary["check_ok"]


def test_editing_a_1000_waypoint_mission_keeps_the_page_equal_to_the_server(browser, tmp_path):
    """The page keeps its copy of a 1 000-waypoint mission by the edits' splices: after drags (one onto the
    seamount), an insert, a delete and an undo, it holds the server's waypoints to the bit, and what it
    shows is an independent ``fly_check`` of them (least altitude; the legs too low, listed and marked)."""
    session = make_session("showcase", [str(tmp_path)])
    from auvplan.serve.app import make_app

    m, t = session.mission, session.world.terrain
    n = 1000
    w = np.linspace(m.start, m.goal, n)
    w[1:-1, 0] += np.where(np.arange(1, n - 1) % 2 == 0, 40.0, -40.0)
    w[1:-1, 2] = -2300.0
    session._apply(w, "test", "1 000 waypoints")
    i, j = np.unravel_index(np.argmax(t.z), t.z.shape)
    summit = (float(t.x[j]), float(t.y[i]))
    with running(make_app(session)) as url:
        page, errors, _ = _page(browser, url)
        assert len(page.evaluate("() => window.auvplan.waypoints()")) == n
        page.evaluate("() => window.auvplan.call('/api/edit', {op: 'depth', index: 500, z: -2450})")
        _drag(page, session.waypoints[500, :2], summit)  # the drag picks the waypoint under the mouse
        _drag(page, session.waypoints[200, :2], session.waypoints[200, :2] + np.array([400.0, 300.0]))
        page.evaluate("([x, y]) => window.auvplan.call('/api/edit', {op: 'insert', x, y})",
                      [float(w[700, 0]) + 100.0, float(w[700, 1])])
        page.evaluate("() => window.auvplan.call('/api/edit', {op: 'delete', index: 10})")
        page.evaluate("() => window.auvplan.call('/api/undo', {})")
        page.wait_for_function("() => document.body.dataset.pending === '0'")
        before = session.waypoints.copy()  # an edit picked on an old picture (revision 0) is refused
        page.evaluate("() => window.auvplan.call('/api/edit', {op: 'delete', index: 10, rev: 0})")
        assert "the mission changed" in page.get_attribute("body", "data-error")
        np.testing.assert_array_equal(session.waypoints, before)
        shown_w = np.array(page.evaluate("() => window.auvplan.waypoints()"))
        np.testing.assert_array_equal(shown_w, session.waypoints)  # the server's mission, to the bit
        assert shown_w.shape[0] == n + 1
        oracle = fly_check(session.world, shown_w, "held")
        low = np.flatnonzero(oracle.leg_altitude_m < oracle.required_altitude_m - 1e-6).tolist()
        assert low  # the waypoint dragged onto the summit is in the rock
        shown = page.evaluate("() => window.auvplan.state().check.violations.filter(v => v.kind === 'altitude')"
                              ".map(v => [v.leg, v.value])")
        assert [s[0] for s in shown] == low
        np.testing.assert_allclose([s[1] for s in shown], oracle.leg_altitude_m[low], atol=1e-9)
        listed = page.evaluate("() => [...document.querySelectorAll(\"#violations li[data-kind='altitude']\")]"
                               ".map(li => Number(li.dataset.leg))")
        first = session.result.violations[:200]  # the panel lists the first 200 (then "… and N more")
        assert listed == [v["leg"] for v in first if v["kind"] == "altitude"]
        assert page.inner_text("#violations li.more") == f"… and {len(session.result.violations) - 200} more"
        marks = page.evaluate("() => document.getElementById('chart').data.find(t => t.name === 'violation at leg')"
                              ".customdata")
        assert len(marks) == len({v["leg"] for v in session.result.violations})  # one mark per leg with a violation
        assert float(page.get_attribute("#min-alt", "data-value")) == pytest.approx(oracle.min_altitude_m, abs=1e-9)
        route = page.evaluate("() => { const d = document.getElementById('chart').data[0]; return [d.x, d.y]; }")
        np.testing.assert_array_equal(np.array(route).T, shown_w[:, :2])  # the drawn route is the mission
        assert [e for e in errors if "409 (Conflict)" not in e] == [], errors  # the refused edit's only
        assert len(errors) == 1
