"""Report, figures and exports of a real run (dynamic-terrain): round trips through independent
parsers, the RunRecord on disk, the report's size and offline-ness, and a headless browser."""

from __future__ import annotations

import json
import os
import re
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from auvplan.cli import main
from auvplan.io.data.geo import LocalFrame
from auvplan.io.missions.formats import parse_moos
from auvplan.io.results import records
from auvplan.io.scenario import loader as sc
from auvplan.sim import RunRecord, decimate


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("run") / "dt"
    assert main(["run", "dynamic-terrain", "--out", str(out)]) == 0
    return out


@pytest.fixture(scope="module")
def world_mission():
    return sc.build(sc.load("dynamic-terrain"))


def test_run_writes_the_report_and_every_export(run_dir):
    for name in ("report.html", "mission.geojson", "mission.kml", "mission.csv", "mission.moos", "run.json",
                 "run.npz"):
        assert (run_dir / name).is_file(), name


def test_run_record_round_trips_through_json_and_npz(run_dir):
    record, text = records.read_run(run_dir)
    rec = json.loads((run_dir / "run.json").read_text())
    assert record.status.value == rec["status"] == "EXACT"
    assert text == sc.resolve("dynamic-terrain").read_text()
    np.testing.assert_allclose(record.keys, np.asarray(rec["key_waypoints"]))
    again = records.run_record(record)
    assert again["simulation"]["distance_m"] == pytest.approx(rec["simulation"]["distance_m"], rel=1e-12)
    assert again["plan"]["cost"] == pytest.approx(rec["plan"]["cost"], rel=1e-12)
    np.testing.assert_allclose(np.loadtxt(run_dir / "track.csv", delimiter=",", skiprows=1)[:, 1:4],
                               decimate(record.sim).position, atol=1e-3)  # decimated; run.npz keeps all


def test_read_run_names_the_missing_file(tmp_path):
    from auvplan.errors import DataError

    with pytest.raises(DataError, match="run.json"):
        records.read_run(tmp_path)
    assert main(["report", str(tmp_path)]) == 2


def test_geojson_is_valid_and_round_trips_to_the_local_frame(run_dir, world_mission):
    shapely = pytest.importorskip("shapely.geometry")
    world, _ = world_mission
    record, _ = records.read_run(run_dir)
    doc = json.loads((run_dir / "mission.geojson").read_text())
    assert doc["type"] == "FeatureCollection"
    track = doc["features"][0]
    geom = shapely.shape(track["geometry"])
    assert geom.geom_type == "LineString" and geom.is_valid and geom.has_z
    c = np.asarray(track["geometry"]["coordinates"])
    assert np.all(np.abs(c[:, 0]) <= 180) and np.all(np.abs(c[:, 1]) <= 90)  # RFC 7946: lon, lat order
    x, y = LocalFrame(*world.origin).forward(c[:, 0], c[:, 1])
    flown = decimate(record.sim).position
    assert np.abs(np.column_stack([x, y]) - flown[:, :2]).max() < 0.01
    np.testing.assert_allclose(c[:, 2], flown[:, 2], atol=1e-3)  # elevation, negative below
    assert track["properties"]["status"] == "EXACT" and track["properties"]["sim_arrived"] is True
    keys = [f for f in doc["features"] if f["properties"]["name"] == "key waypoints"][0]
    assert shapely.shape(keys["geometry"]).geom_type == "MultiPoint"


def test_kml_parses_back_to_the_track(run_dir, world_mission):
    world, _ = world_mission
    record, _ = records.read_run(run_dir)
    root = ET.parse(run_dir / "mission.kml").getroot()
    ns = {"k": "http://www.opengis.net/kml/2.2"}
    ls = root.find("k:Document/k:Placemark/k:LineString", ns)
    assert ls.find("k:altitudeMode", ns).text == "absolute"
    c = np.array([[float(v) for v in p.split(",")] for p in ls.find("k:coordinates", ns).text.split()])
    x, y = LocalFrame(*world.origin).forward(c[:, 0], c[:, 1])
    assert np.abs(np.column_stack([x, y, c[:, 2]]) - decimate(record.sim).position).max() < 0.01


def test_moos_block_parses_back_to_the_mission(run_dir):
    record, _ = records.read_run(run_dir)
    text = (run_dir / "mission.moos").read_text()
    assert text.count("Behavior = BHV_Waypoint") == 1
    np.testing.assert_allclose(parse_moos(text), record.route, atol=0.001)


def test_csv_has_local_geographic_depth_and_time_columns(run_dir, world_mission):
    world, mission = world_mission
    record, _ = records.read_run(run_dir)
    rows = np.genfromtxt(run_dir / "mission.csv", delimiter=",", names=True)
    assert rows.dtype.names == ("x", "y", "z", "lat", "lon", "depth", "time", "speed")
    np.testing.assert_allclose(rows["speed"], mission.vehicle.speed)  # every leg at the cruise speed (issue 38)
    np.testing.assert_allclose(np.column_stack([rows["x"], rows["y"], rows["z"]]), record.route, atol=1e-3)
    np.testing.assert_allclose(rows["depth"], -rows["z"])
    legs = np.linalg.norm(np.diff(record.route, axis=0), axis=1)
    np.testing.assert_allclose(np.diff(rows["time"]), legs / mission.vehicle.speed, atol=0.011)
    lon, lat = LocalFrame(*world.origin).inverse(rows["x"], rows["y"])
    np.testing.assert_allclose(rows["lat"], lat, atol=1e-8)


def test_export_command_and_the_local_only_scenario(tmp_path):
    out = tmp_path / "single"
    assert main(["run", "track-single", "--out", str(out)]) in (0, 1)
    assert not (out / "mission.geojson").exists()  # no [origin]: geographic formats left out
    assert main(["export", str(out), "--format", "geojson"]) == 2
    assert main(["export", str(out), "--format", "moos", "csv"]) == 0
    assert (out / "mission.moos").is_file() and (out / "report.html").is_file()


def test_report_is_small_offline_and_has_every_section(run_dir):
    page = (run_dir / "report.html").read_text()
    assert len(page.encode()) < 10_000_000
    from html.parser import HTMLParser

    class Sources(HTMLParser):
        found: list = []

        def handle_starttag(self, tag, attrs):
            self.found += [v for k, v in attrs if k in ("src", "href")]

    parser = Sources()
    parser.feed(page)
    assert parser.found == []  # nothing loaded from anywhere: plotly.js is inlined
    assert page.count("<script") >= 5 and "Plotly.newPlot" in page
    for div in ("view3d", "planview", "profiles", "convergence"):
        assert f'id="{div}"' in page
    assert '<table id="metrics">' in page and "<pre id='scenario'>" in page


def test_report_command_rebuilds_it_with_figures(run_dir, tmp_path):
    copy = tmp_path / "copy"
    shutil.copytree(run_dir, copy)
    (copy / "report.html").unlink()
    assert main(["report", str(copy), "--figures"]) == 0
    assert (copy / "report.html").stat().st_size > 1_000_000
    for name in ("plan_view", "profiles", "convergence"):
        png = copy / "figures" / f"{name}.png"
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 20_000
        assert (copy / "figures" / f"{name}.svg").read_text().lstrip().startswith("<?xml")


def test_paper_figures_draw_every_path(world_mission):
    from auvplan.viz import plots

    world, _ = world_mission
    paths = {n: np.array([[37000.0 + i, 57000.0, -2500.0], [43000.0, 63000.0 - i, -2400.0]])
             for i, n in enumerate(("iabc", "abc", "ga", "pso"))}
    fig = plots.algorithm_paths(world, paths)
    assert [ln.get_label() for ln in fig.axes[0].lines] == list(paths)
    fig = plots.convergence({n: np.linspace(10, 1, 5) for n in paths})
    assert len(fig.axes[0].lines) == 4
    from auvplan.world import Bounds, Sphere, World

    w = World(Bounds(-20, 20, -20, 20, -20, 20), obstacles=(Sphere((0.0, 0.0, 0.0), 3.0),))
    lines = [np.array([[-10.0, k, 0.0], [10.0, k, 0.0]]) for k in (-5.0, 5.0)]
    fig = plots.streamlines(w, lines, np.array([12.0, 0.0, 0.0]))
    assert sum(len(ax.lines) for ax in fig.axes) == 2 * (len(lines) + 1)


def _chromium() -> str | None:
    return shutil.which("chromium") or shutil.which("chromium-browser")


@pytest.fixture(scope="module")
def browser():
    """Headless Chromium, launched once for the module's pages (each test opens its own page)."""
    path = _chromium()
    if path is None:
        if os.environ.get("CI"):
            pytest.fail("Chromium is not installed on CI (tools/install-chromium.sh should have installed it)")
        pytest.skip("Chromium is not installed (Debian package 'chromium'; tools/install-chromium.sh)")
    sync_api = pytest.importorskip("playwright.sync_api")
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=path,
                              args=["--no-sandbox", "--use-gl=swiftshader", "--enable-unsafe-swiftshader"])
        yield b
        b.close()


_CHART_JS = """() => {
    const m = document.getElementById('planview');
    const scatter = [...m.querySelectorAll('.scatterlayer .trace')];
    const coast = m._fullData.findIndex(t => t.name === 'coastline');
    const nth = m._fullData.filter((t, i) => i < coast && t.type === 'scatter').length;
    const line = coast < 0 ? null : scatter[nth].querySelector('path.js-line');
    const drawn = line ? (line.getAttribute('d') || '') : '';
    const boxes = [...m.querySelectorAll('.annotation')].map(a => {
        const r = a.getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom, a.textContent]; });
    const overlaps = [];
    for (let i = 0; i < boxes.length; i++) for (let j = i + 1; j < boxes.length; j++) {
        const a = boxes[i], b = boxes[j];
        const hit = a[0] < b[2] - 0.5 && b[0] < a[2] - 0.5 && a[1] < b[3] - 0.5 && b[1] < a[3] - 0.5;
        if (hit) overlaps.push([a[4], b[4]]);
    }
    return {isobaths: m._fullData.filter(t => t.meta && t.meta.kind === 'isobath').map(t => t.meta.level),
            coast: drawn.length, labels: boxes.map(b => b[4]), overlaps: overlaps};
}"""

_LOOK_JS = """() => {
    const v = document.getElementById('view3d'), m = document.getElementById('planview');
    const seabed = v.data.find(t => t.name === 'seabed'), chart = m.data.find(t => t.name === 'seabed');
    const meshes = v._fullData.filter(t => t.type === 'mesh3d' && t.x.length).map(t => {
        const n = t.x.length, c = [t.x, t.y, t.z].map(a => (Math.max(...a) + Math.min(...a)) / 2);
        let r = 0;
        for (let i = 0; i < n; i++) r = Math.max(r, Math.hypot(t.x[i] - c[0], t.y[i] - c[1], t.z[i] - c[2]));
        return {name: t.name, radius: r, stated: t.meta.radius};
    });
    return {seabed: JSON.stringify([seabed.colorscale, seabed.cmin, seabed.cmax]),
            chart: JSON.stringify([chart.colorscale, chart.zmin, chart.zmax]),
            zrange: v.layout.scene.zaxis.range, meshes: meshes,
            labels: v.layout.sliders[0].steps.map(s => s.label),
            graticule: m.layout.annotations.map(a => a.text)};
}"""


@pytest.fixture(scope="module")
def report_in_browser(run_dir, browser, tmp_path_factory):
    """The run's report opened once, offline, in Chromium: console errors and outside requests, the 3D plot's
    and the chart's state (``_LOOK_JS``), the chart's labels (``_CHART_JS``, before any click), the vehicle's x
    before and after a click on the time slider, and a screenshot."""
    from playwright.sync_api import TimeoutError as PlaywrightTimeout

    page = browser.new_page(viewport={"width": 1300, "height": 900})
    page.set_default_timeout(120_000)  # a safety net on a loaded machine (the waits end on a state), not an oracle
    errors, requests = [], []
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.on("request", lambda r: requests.append(r.url) if not r.url.startswith(("file:", "data:", "blob:"))
            else None)
    page.goto((run_dir / "report.html").as_uri())
    page.wait_for_selector("#view3d canvas", state="attached", timeout=120_000)
    page.wait_for_selector("#planview .annotation", state="attached", timeout=120_000)
    page.wait_for_selector("#view3d .slider-rail-rect", state="visible", timeout=120_000)  # both plots drawn
    page.evaluate("() => document.fonts.ready.then(() => new Promise(r => requestAnimationFrame(() => "
                  "requestAnimationFrame(r))))")  # and laid out with their fonts: two frames since
    got = {"scene": page.evaluate("() => document.getElementById('view3d').layout.scene !== undefined"),
           "metrics_rows": page.locator("#metrics tr").count(), "chart": page.evaluate(_CHART_JS)}
    vehicle = "() => document.getElementById('view3d').data.find(t => t.name === 'vehicle').x[0]"
    got["x0"] = page.evaluate(vehicle)
    got["look"] = page.evaluate(_LOOK_JS)
    rail = page.locator("#view3d .slider-rail-rect").first.bounding_box()
    page.mouse.click(rail["x"] + 0.7 * rail["width"], rail["y"] + rail["height"] / 2)
    try:  # the slider's frame is drawn asynchronously: wait for the vehicle to move (no fixed pause)
        page.wait_for_function(f"() => ({vehicle})() !== {json.dumps(got['x0'])}", timeout=120_000)
    except PlaywrightTimeout:
        pass  # the test's assertion names it: the vehicle did not move
    got["x1"] = page.evaluate(vehicle)
    got["screenshot"] = tmp_path_factory.mktemp("browser") / "report.png"
    page.screenshot(path=str(got["screenshot"]))
    page.close()
    return {**got, "errors": errors, "requests": requests}


def test_report_in_a_headless_browser(report_in_browser, run_dir, world_mission):
    """Chromium opens the report offline: no console error, the 3D plot and the metrics table
    render, and the time slider moves the vehicle."""
    got, look = report_in_browser, report_in_browser["look"]
    assert got["scene"] and got["metrics_rows"] >= 10
    assert got["errors"] == [] and got["requests"] == []
    world, _ = world_mission
    # One colour scale for the seabed: the 3D surface and the chart share its definition and range.
    assert look["seabed"] == look["chart"]
    b = world.bounds
    assert b.zmin <= look["zrange"][0] < look["zrange"][1] <= b.zmax
    radii = {o.name: o.shape.bounding_radius for o in world.moving}
    drawn = {m["name"]: m for m in look["meshes"] if m["name"] in radii}
    assert set(drawn) == set(radii)
    for name, m in drawn.items():
        assert m["stated"] == pytest.approx(radii[name]) and m["radius"] == pytest.approx(radii[name], rel=1e-3)
    assert len(look["labels"]) > 10 and all(re.fullmatch(r"\d+:\d\d:\d\d", s) for s in look["labels"])
    assert any(t.endswith("°E") for t in look["graticule"]) and any(t.endswith("°N") for t in look["graticule"])
    record, _ = records.read_run(run_dir)
    x0, x1 = got["x0"], got["x1"]
    assert x1 != x0 and record.sim.position[:, 0].min() <= x1 <= record.sim.position[:, 0].max()
    assert got["screenshot"].stat().st_size > 50_000


def _chart_in_browser(browser, html_path: Path) -> dict:
    page = browser.new_page(viewport={"width": 1300, "height": 900})
    page.set_default_timeout(120_000)  # a safety net on a loaded machine (the waits end on a state), not an oracle
    page.goto(html_path.as_uri())
    page.wait_for_selector("#planview .annotation", state="attached", timeout=120_000)
    look = page.evaluate(_CHART_JS)
    page.close()
    return look


def test_chart_of_a_real_coast_in_a_browser(browser, tmp_path):
    """The chart rules on a real area (admiralty-inlet: topobathy + GSHHG shoreline, 36 km): a dozen or
    so isobaths at a round interval, the coastline drawn, and no two labels overlapping on the page."""
    from auvplan.viz.chart import figure_plan_view

    world, mission = sc.build(sc.load("admiralty-inlet"))
    route = np.array([mission.start, mission.goal])
    keys = np.array([mission.start, 0.5 * (np.asarray(mission.start) + mission.goal), mission.goal])
    record = RunRecord("admiralty-inlet", 0, None, route, keys, None)
    page = tmp_path / "chart.html"
    figure_plan_view(world, record).write_html(page, include_plotlyjs=True, div_id="planview")
    look = _chart_in_browser(browser, page)
    levels = np.array(look["isobaths"])
    assert 8 <= levels.size <= 25 and np.all(levels < 0)
    step = float(np.min(np.diff(np.sort(levels))))
    assert step in (1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0)
    assert look["coast"] > 200  # an SVG path of the shoreline, not an empty trace
    assert {"goal", "K1"} <= set(look["labels"]) and sum(t.isdigit() for t in look["labels"]) >= 5
    assert look["overlaps"] == []


def test_report_chart_labels_do_not_overlap(report_in_browser):
    look = report_in_browser["chart"]  # the report's page as it loaded, before the slider was clicked
    assert look["overlaps"] == [] and look["isobaths"] and "K1" in look["labels"]
