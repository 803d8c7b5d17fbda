"""``[[zones]] file`` on real charts, one test per reader format: an S-57 electronic chart read by object
class (a cut of NOAA ENC US4MD81M, ``tests/data/US4MD81M_zones.000``, provenance in tests/data/PROVENANCE.md),
Natural Earth's reef lines (GeoJSON, shipped), and the chart's real features as GDAL writes them to KML,
Shapefile and GeoPackage in other CRSs.

Oracles: geodesic areas and lengths on the WGS 84 ellipsoid (``pyproj.Geod``, no map projection), the
features' own lon/lat (a wreck's position, the chart's object names), and the S-57 read itself for the
other formats (same features, so the same footprints)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pyogrio
import pytest
import shapely
from pyproj import Geod, Transformer

from auvplan.io.data.geo import LocalFrame
from auvplan.io.scenario.build import build
from auvplan.io.scenario.loader import loads

CELL = Path(__file__).resolve().parents[1] / "data" / "US4MD81M_zones.000"
ORIGIN = (38.8, -76.4)  # Chesapeake Bay, the cell's middle
GEOD = Geod(ellps="WGS84")


def _world(zones_toml: str, base: Path | None = None):
    text = f"""
[origin]
lat = {ORIGIN[0]}
lon = {ORIGIN[1]}
[bounds]
x = [-40000.0, 40000.0]
y = [-40000.0, 40000.0]
z = [-50.0, 0.0]
[terrain.synthetic]
kind = "flat"
depth = 40.0
[mission]
start = [-30000.0, -30000.0, -10.0]
goal = [30000.0, 30000.0, -10.0]
min_altitude_m = 5.0
{zones_toml}
"""
    return build(loads(text, source="chart.toml", base_dir=base))[0]


def _features(layer: str) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    meta, _, wkb, fields = pyogrio.raw.read(CELL, layer=layer, read_geometry=True)
    return shapely.from_wkb(wkb), dict(zip(meta["fields"].tolist(), fields, strict=True))


def test_gdal_reads_s57():
    assert "S57" in pyogrio.list_drivers()


def test_an_s57_chart_by_object_class_restricted_areas_wrecks_pipelines_obstructions():
    world = _world(f"""
[[zones]]
name = "restricted"
file = "{CELL}"
layer = "RESARE"
[[zones]]
name = "wreck"
file = "{CELL}"
layer = "WRECKS"
radius_m = 50.0
above_seabed_m = 10.0
[[zones]]
name = "pipeline"
file = "{CELL}"
layer = "PIPSOL"
buffer_m = 30.0
[[zones]]
name = "obstruction"
file = "{CELL}"
layer = "OBSTRN"
[[zones]]
name = "cable area"
file = "{CELL}"
layer = "CBLARE"
""")
    zones = {z.name: z for z in world.zones.exact.zones}
    frame = LocalFrame(*ORIGIN)
    box = shapely.box(-41000.0, -41000.0, 41000.0, 41000.0)
    for layer, prefix in (("RESARE", "restricted"), ("WRECKS", "wreck"), ("PIPSOL", "pipeline"),
                          ("OBSTRN", "obstruction"), ("CBLARE", "cable area")):
        geoms, fields = _features(layer)
        mine = [z for n, z in zones.items() if n.startswith(prefix + ": ")]
        near = [g for g in geoms if shapely.intersects(shapely.transform(g, lambda xy: np.column_stack(
            frame.forward(xy[:, 0], xy[:, 1]))), box)]
        assert len(mine) == len(near) > 0, layer
    assert "restricted: Naval Research Laboratory" in zones  # the chart's OBJNAM
    geoms, fields = _features("RESARE")
    nrl = geoms[list(fields["OBJNAM"]).index("Naval Research Laboratory")]
    area = abs(GEOD.geometry_area_perimeter(nrl)[0])  # m², on the ellipsoid
    assert shapely.area(zones["restricted: Naval Research Laboratory"].footprint) == pytest.approx(area, rel=2e-3)
    wrecks, _ = _features("WRECKS")
    for k, g in enumerate(wrecks):
        z = zones.get(f"wreck: #{k + 1}")
        if g.geom_type != "Point" or z is None:
            continue
        x, y = frame.forward(g.x, g.y)
        assert shapely.distance(shapely.Point(float(x), float(y)), shapely.boundary(z.footprint)) >= 50.0 - 1e-6
        assert math.pi * 50.0**2 < shapely.area(z.footprint) < 1.003 * math.pi * 50.0**2
        assert z.above_seabed == 10.0
    pipes, _ = _features("PIPSOL")
    for k, g in enumerate(pipes):
        length = GEOD.geometry_length(g)
        a = shapely.area(zones[f"pipeline: #{k + 1}"].footprint)
        assert 2 * 30.0 * length * 0.998 < a < (2 * 30.0 * length + math.pi * 30.0**2) * 1.004


def _s57_footprints(layer: str) -> list:
    world = _world(f'[[zones]]\nname = "c"\nfile = "{CELL}"\nlayer = "{layer}"\n')
    return [z.footprint for z in world.zones.exact.zones]


@pytest.mark.parametrize(("suffix", "driver", "crs"), [("kml", "KML", "EPSG:4326"),
                                                       ("shp", "ESRI Shapefile", "EPSG:26918"),  # UTM 18N
                                                       ("gpkg", "GPKG", "EPSG:3857")])
def test_the_charts_features_in_other_formats_and_crss_read_to_the_same_footprints(tmp_path, suffix, driver, crs):
    geoms, fields = _features("RESARE")
    to = Transformer.from_crs("EPSG:4326", crs, always_xy=True)
    moved = [shapely.transform(g, lambda xy: np.column_stack(to.transform(xy[:, 0], xy[:, 1]))) for g in geoms]
    names = np.array([n if n else "" for n in fields["OBJNAM"]], dtype=object)
    pyogrio.raw.write(tmp_path / f"areas.{suffix}", np.array(shapely.to_wkb(moved), dtype=object), [names],
                      ["OBJNAM"], driver=driver, crs=crs, geometry_type="Polygon", layer="areas")
    world = _world(f'[[zones]]\nname = "c"\nfile = "areas.{suffix}"\nlayer = "areas"\n', tmp_path)
    got = [z.footprint for z in world.zones.exact.zones]
    want = _s57_footprints("RESARE")
    assert len(got) == len(want) == len(geoms)
    for a, b in zip(got, want, strict=True):
        assert shapely.area(shapely.symmetric_difference(a, b)) < 1e-3 * shapely.area(b)


def test_natural_earth_reefs_geojson_as_shipped():
    from importlib import resources

    path = Path(str(resources.files("auvplan") / "data" / "ne_10m_reefs_chagos.geojson"))
    meta, _, wkb, fields = pyogrio.raw.read(path, read_geometry=True)
    lines = shapely.from_wkb(wkb)
    names = list(fields[list(meta["fields"]).index("name")])
    text = f"""
[origin]
lat = -6.3
lon = 71.8
[bounds]
x = [-60000.0, 160000.0]
y = [-130000.0, 130000.0]
z = [-500.0, 0.0]
[terrain.synthetic]
kind = "flat"
depth = 400.0
[mission]
start = [-50000.0, 0.0, -100.0]
goal = [0.0, 100000.0, -100.0]
min_altitude_m = 20.0
[[zones]]
name = "reef"
file = "{path}"
buffer_m = 1000.0
"""
    world = build(loads(text, source="reefs.toml"))[0]
    zones = {z.name: z for z in world.zones.exact.zones}
    assert set(zones) == {f"reef: {n}" for n in names}
    for line, name in zip(lines, names, strict=True):
        length = GEOD.geometry_length(line)
        a = shapely.area(zones[f"reef: {name}"].footprint)
        closed = shapely.get_coordinates(line)
        ring = np.allclose(closed[0], closed[-1])
        low = 2 * 1000.0 * length * (0.9 if ring else 0.998)  # a closed ring's buffer overlaps itself inside
        assert low < a < (2 * 1000.0 * length + math.pi * 1000.0**2) * 1.004, name


@pytest.mark.parametrize(("suffix", "driver"), [("shp", "ESRI Shapefile"), ("fgb", "FlatGeobuf"),
                                                ("gdb", "OpenFileGDB"), ("gpkg", "GPKG")])
def test_an_attribute_filter_selects_the_same_features_with_or_without_the_fields(tmp_path, suffix, driver):
    """Oracle: the filter applied by hand to the chart's RESARE features (their OBJNAM).  Without ``fields=True`` the
    reader asked GDAL for no column, and the shapefile, FlatGeobuf and FileGDB drivers then matched no feature."""
    from auvplan.io.data.vector.reader import read_vector

    geoms, fields = _features("RESARE")
    names = np.array([n if n else "" for n in fields["OBJNAM"]], dtype=object)
    path = tmp_path / f"areas.{suffix}"
    pyogrio.raw.write(path, np.array(shapely.to_wkb(geoms), dtype=object), [names], ["OBJNAM"], driver=driver,
                      crs="EPSG:4326", geometry_type="Polygon", layer="areas")
    want = [g for g, n in zip(geoms, names, strict=True) if n == "Naval Research Laboratory"]
    assert len(want) == 1 < len(geoms)
    for asked in (False, True):
        got = read_vector(path, "t", ValueError, where="OBJNAM = 'Naval Research Laboratory'", fields=asked)
        (g,) = got.present()  # a FileGDB's polygon reads back a multipolygon: compared as areas
        assert shapely.area(shapely.symmetric_difference(g, want[0])) < 1e-9 * shapely.area(want[0])
        assert bool(got.fields) is asked  # the columns are returned only when asked for
