"""Land polygons: exact point/segment tests, the burnt seabed, user vector files, GSHHG coastal scenario."""

from __future__ import annotations

import json
from importlib import resources

import numpy as np
import pytest
import shapely
from pyproj import Transformer

from auvplan import cli
from auvplan.io.data.geo import LocalFrame
from auvplan.io.data.vector.coast import LandSpec, read_land
from auvplan.io.scenario import loader as sc
from auvplan.world import Bounds, Land, Margins, Terrain, World

ISLAND = shapely.box(400.0, 400.0, 600.0, 500.0)


def flat(depth=50.0, cell=25.0, size=1000.0):
    x = np.arange(0.0, size + cell / 2, cell)
    return Terrain(x, x, np.full((x.size, x.size), -depth), name="flat")


def test_points_and_signed_distance():
    land = Land(ISLAND, "box")
    pts = np.array([[500.0, 450.0, -5.0], [700.0, 450.0, -5.0], [400.0, 420.0, 0.0], [500.0, 300.0, 0.0]])
    assert land.contains(pts).tolist() == [True, False, True, False]
    assert np.allclose(land.signed_distance(pts), [-50.0, 100.0, 0.0, 100.0])


def test_segments_hit_is_exact_at_the_corner():
    land = Land(ISLAND, "box")
    # diagonal segments past the corner (600, 500): through it by 1 mm, or clear of it by 1 mm
    seg = np.array([
        [[500.0, 600.001, -5.0], [700.0, 400.001, -5.0]],   # x + y = 1100.001: misses the corner
        [[500.0, 599.999, -5.0], [700.0, 399.999, -5.0]],   # x + y = 1099.999: cuts it
        [[0.0, 450.0, -5.0], [1000.0, 450.0, -5.0]],        # straight across
        [[500.0, 450.0, -5.0], [500.0, 450.0, -5.0]],       # a point on land
        [[0.0, 0.0, -5.0], [100.0, 100.0, -5.0]],
    ])
    assert land.segments_hit(seg).tolist() == [False, True, True, True, False]
    # the same through the World, whose seabed is raised over the island
    w = World(Bounds(0, 1000, 0, 1000, -50, 0), flat(), land=land, margins=Margins(min_altitude=2.0))
    assert w.segments_free(seg, moving=False).tolist() == [False, False, False, False, True]
    assert not w.is_free([500.0, 450.0, -5.0])
    assert "on land" in w.explain([500.0, 450.0, -5.0])


def test_burn_covers_every_cell_touching_land_and_implies_the_polygon_test():
    """Oracle: independent brute force over the cells, then random segments — any segment that keeps
    its exact altitude >= 0 below the surface never meets the polygon."""
    tri = shapely.Polygon([(310.0, 320.0), (690.0, 380.0), (480.0, 720.0)])
    land = Land(tri, "tri")
    t = land.burn(flat(cell=40.0))
    x, y = t.x, t.y
    for j in range(y.size - 1):
        for i in range(x.size - 1):
            if tri.intersects(shapely.box(x[i], y[j], x[i + 1], y[j + 1])):
                assert t.z[j:j + 2, i:i + 2].min() >= 1.0
    rng = np.random.default_rng(7)
    a = np.column_stack([rng.uniform(0, 1000, (4000, 2)), rng.uniform(-49, -0.5, 4000)])
    b = np.column_stack([rng.uniform(0, 1000, (4000, 2)), rng.uniform(-49, -0.5, 4000)])
    seg = np.stack([a, b], axis=1)
    ok = t.segment_min_altitude(seg) >= 0.0
    assert ok.sum() > 500 and (~ok).sum() > 500
    assert not land.segments_hit(seg[ok]).any()


def _gpkg(tmp_path, geoms, crs, name="coast.gpkg", layer="land", geometry_type="Polygon"):
    import pyogrio

    p = tmp_path / name
    pyogrio.raw.write(p, geometry=shapely.to_wkb(np.asarray(geoms, dtype=object)), field_data=[], fields=[],
                      crs=crs, geometry_type=geometry_type, driver="GPKG", layer=layer)
    return p


def test_user_geopackage_in_utm_is_projected(tmp_path):
    frame = LocalFrame(48.1, -122.9)
    utm = Transformer.from_crs("EPSG:4326", "EPSG:32610", always_xy=True)
    e0, n0 = utm.transform(-122.9, 48.1)
    poly = shapely.box(e0 + 1000.0, n0 + 2000.0, e0 + 3000.0, n0 + 2500.0)
    p = _gpkg(tmp_path, [poly], "EPSG:32610")
    land = read_land(LandSpec(file=p.name), frame, (0.0, 10_000.0, 0.0, 10_000.0), base_dir=tmp_path)
    # independent: every UTM vertex → lon/lat → local frame with pyproj, compared with the polygon
    back = Transformer.from_crs("EPSG:32610", "EPSG:4326", always_xy=True)
    lon, lat = back.transform(*np.asarray(poly.exterior.coords).T)
    x, y = frame.forward(lon, lat)
    assert np.allclose(land.signed_distance(np.column_stack([x, y])), 0.0, atol=1e-6)
    cx, cy = frame.forward(*back.transform(e0 + 2000.0, n0 + 2250.0))
    assert land.contains(np.array([[cx, cy]]))[0]


def test_bad_land_files_exit_2(tmp_path, capsys):
    lines = _gpkg(tmp_path, [shapely.LineString([(-122.9, 48.1), (-122.8, 48.2)])], "EPSG:4326", "lines.gpkg",
                  geometry_type="LineString")
    base = sc.resolve("admiralty-inlet").read_text()
    for text, words in [
        (base.replace('builtin = "gshhg-juan-de-fuca"', f'file = "{lines.name}"'), ("lines.gpkg", "geometry",
                                                                                     "no polygons")),
        (base.replace('builtin = "gshhg-juan-de-fuca"', 'file = "missing.shp"'), ("missing.shp", "not found")),
        (base.replace('builtin = "gshhg-juan-de-fuca"', f'file = "{lines.name}"\nlayer = "nope"'),
         ("lines.gpkg", "layer 'nope'")),
        (base.replace('builtin = "gshhg-juan-de-fuca"', 'builtin = "atlantis"'), ("[land]", "builtin", "atlantis")),
    ]:
        s = tmp_path / "s.toml"
        s.write_text(text)
        assert cli.main(["validate", str(s)]) == 2
        err = capsys.readouterr().err
        assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err
        for w in words:
            assert w in err, (w, err)


# ---------------------------------------------------------------------- the coastal scenario
@pytest.fixture(scope="module")
def admiralty():
    s = sc.load("admiralty-inlet")
    world, mission = sc.build(s)
    return s, world, mission


def _gshhg_in_frame(s):
    """The shipped GSHHG polygons read with json + shapely and projected vertex by vertex (independent of
    io.coast: no clipping, no densifying)."""
    path = resources.files("auvplan") / "data" / "gshhg_h_juan_de_fuca.geojson"
    geom = shapely.from_geojson(json.dumps(json.loads(path.read_text())))
    frame = LocalFrame(s.origin.lat, s.origin.lon)
    return shapely.transform(geom, lambda xy: np.column_stack(frame.forward(xy[:, 0], xy[:, 1])))


def test_land_matters_in_the_coastal_scenario(admiralty):
    s, world, mission = admiralty
    gshhg = _gshhg_in_frame(s)
    straight = shapely.LineString([mission.start[:2], mission.goal[:2]])
    assert straight.intersects(gshhg)  # the direct route crosses the Quimper Peninsula
    assert world.land.segments_hit(np.array([[mission.start, mission.goal]]))[0]


@pytest.mark.parametrize("planner, seed", [("iabc", 0), ("iabc", 1), ("iabc", 2), ("grid", 0)])
def test_plans_never_cross_gshhg_land(admiralty, planner, seed):
    from dataclasses import replace

    from auvplan.planners import plan
    from auvplan.sim import planning_problem

    s, world, mission = admiralty
    spec = replace(mission.planner, name=planner)
    r = plan(planning_problem(world, mission), spec, rng=seed)
    assert r.status.ok
    path = np.asarray(r.path)
    segs = np.stack([path[:-1], path[1:]], axis=1)
    gshhg = _gshhg_in_frame(s)
    lines = shapely.linestrings(segs[..., :2])
    assert not shapely.intersects(lines, gshhg).any()  # exact, on the unclipped GSHHG polygons
    assert world.segments_free(segs, moving=False).all()

