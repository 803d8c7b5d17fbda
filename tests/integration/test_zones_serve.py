"""``auvplan serve`` on the zones built-in: the chart draws every zone with its name, and an edit that
takes a leg into a zone is flagged naming the zone and the leg (oracle: shapely's own intersection of
the leg's trace with the footprint; the built-in's zones reach from the surface to the seabed)."""

from __future__ import annotations

import base64

import numpy as np
import pytest
import shapely

pytest.importorskip("starlette")
from starlette.testclient import TestClient  # noqa: E402

from auvplan.cli.serve import make_session  # noqa: E402
from auvplan.serve.app import make_app  # noqa: E402


@pytest.fixture(scope="module")
def reefs(tmp_path_factory):
    session = make_session("chagos-reefs", [str(tmp_path_factory.mktemp("served"))])
    return session, TestClient(make_app(session), base_url="http://127.0.0.1")


def _array(v):
    """A plotly JSON array: a list, or a typed array ``{dtype, bdata}`` (base64)."""
    if isinstance(v, dict):
        return np.frombuffer(base64.b64decode(v["bdata"]), dtype=v["dtype"]).astype(float)
    return np.array([np.nan if e is None else e for e in v], dtype=float)


def test_the_chart_draws_every_zone_in_the_bounds_with_its_name(reefs):
    """The page's chart is the report's (``viz.chart.figure_plan_view``): each zone's filled outline is its
    footprint cut to the bounds (same area), and its name is written on it."""
    session, client = reefs
    chart = client.get("/api/chart").json()
    traces = {t["meta"]["name"]: t for t in chart["data"] if isinstance(t.get("meta"), dict)
              and t["meta"].get("kind") == "zone"}
    b = session.world.bounds
    box = shapely.box(b.xmin, b.ymin, b.xmax, b.ymax)
    inside = {z.name: shapely.intersection(z.footprint, box) for z in session.world.zones.exact.zones
              if shapely.intersects(z.footprint, box)}
    assert inside and set(traces) == set(inside)
    labels = {a["text"]: (a["x"], a["y"]) for a in chart["layout"].get("annotations", [])
              if a.get("name") == "label-zone"}
    for name, shown in inside.items():
        xs, ys = (_array(traces[name][k]) for k in "xy")
        rings = [np.column_stack([x[np.isfinite(x)], y[np.isfinite(y)]]) for x, y in
                 zip(np.split(xs, np.flatnonzero(np.isnan(xs))), np.split(ys, np.flatnonzero(np.isnan(ys))),
                     strict=True)]
        rings = [r for r in rings if r.shape[0] >= 4]
        drawn = shapely.area(shapely.Polygon(rings[0], rings[1:]))  # one polygon per zone here: shell, holes
        assert drawn == pytest.approx(shapely.area(shown), rel=1e-6), name
        assert name in labels and shapely.distance(shapely.Point(labels[name]), shown) < 1.0, name


def _oracle(zones, w):
    """Every (leg, message) whose trace meets a footprint (surface-to-seabed zones: any depth enters)."""
    out = set()
    for leg in range(len(w) - 1):
        trace = shapely.LineString(w[leg:leg + 2, :2])
        for z in zones.zones:
            assert z.above_seabed is None and z.top == 0 and np.isinf(z.bottom)
            if shapely.intersects(trace, z.footprint):
                out.add((leg, f"leg {leg}: enters no-go zone {z.name!r}"))
    return out


def _flagged(st):
    return {(v["leg"], v["text"]) for v in st["check"]["violations"] if v["kind"] == "zone"}


def test_an_edit_into_a_zone_is_flagged_naming_the_zone_and_the_leg(reefs):
    session, client = reefs
    zones = session.world.zones.exact
    st = client.get("/api/state").json()
    opened = _flagged(st)  # the straight start-goal line crosses Salomon atoll: the page opens round it
    assert opened == _oracle(zones, np.array(st["waypoints"])) == set()
    assert st["check"]["summary"]["zone_entries"] == 0
    start, goal = session.mission.start, session.mission.goal
    straight = np.array([start, goal], dtype=float)
    assert {t.split("zone ")[1] for _, t in _oracle(zones, straight)} == {"'reef: Salomon Islands'"}
    target = next(z for z in zones.zones if z.name == "reef: Blenheim Reef")
    inside = shapely.get_coordinates(shapely.point_on_surface(target.footprint))[0]
    st = client.post("/api/edit", json={"op": "insert", "x": float(inside[0]), "y": float(inside[1])}).json()
    w = np.array(st["waypoints"])
    k = next(i for i in range(len(w)) if np.allclose(w[i, :2], inside))
    flagged = _flagged(st)
    assert flagged == _oracle(zones, w)
    blenheim = {leg for leg, text in flagged if "Blenheim" in text}
    assert blenheim >= {k - 1, k}
    assert st["check"]["summary"]["zone_entries"] == len(flagged) and not st["check"]["summary"]["ok"]
    st = client.post("/api/undo", json={}).json()
    assert _flagged(st) == opened
