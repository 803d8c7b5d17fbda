"""fix20: a GeoJSON ``crs`` member GDAL cannot build.  GDAL's GeoJSON driver reads it as WGS 84 — no error, no
warning (``pyogrio.raw.read`` gives ``EPSG:4326`` for ``"EPSG:99999"``, ``"nonsense"`` and a ``link``): a zone
file in a projected CRS with a misspelt ``crs`` lands its zones far from the operating area, or nowhere, and the
check passes.  Now exit 2 naming the file and the member.

Oracles: pyproj's own verdict on each stated CRS (``CRS.from_user_input``); the members GDAL reads rightly (a
``name`` or ``EPSG`` form of EPSG:32633, OGC CRS84, no member) read as before.  And the zone repair warning is
shown on every read, the readers' cache on (its kept log replayed on a hit): the wave-14 note's "only on the first
read" does not reproduce."""

from __future__ import annotations

import json
import logging

import pytest
from pyproj import CRS

from auvplan.cli import main
from auvplan.errors import DataError
from auvplan.io.data.vector.reader import read_vector

_RING = [[500000.0, 100000.0], [500100.0, 100000.0], [500100.0, 100100.0], [500000.0, 100000.0]]


def _geojson(path, crs, ring=_RING):
    doc = {"type": "FeatureCollection",
           "features": [{"type": "Feature", "properties": {"name": "A"},
                         "geometry": {"type": "Polygon", "coordinates": [ring]}}]}
    if crs is not ...:
        doc = {"type": doc["type"], "crs": crs, "features": doc["features"]}
    path.write_text(json.dumps(doc))
    return path


@pytest.mark.parametrize("crs", [
    {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::99999"}},
    {"type": "name", "properties": {"name": "EPSG:32633x"}},
    {"type": "link", "properties": {"href": "http://example.org/crs", "type": "proj4"}},
    {"type": "EPSG", "properties": {"code": 0}},
    "EPSG:32633",
])
def test_a_crs_gdal_cannot_build_is_refused_naming_the_file_and_the_member(tmp_path, crs):
    path = _geojson(tmp_path / "z.geojson", crs)
    with pytest.raises(DataError, match=r"^s\.toml: \[\[zones\]\] file = 'z\.geojson': crs .* cannot be built") as err:
        read_vector(path, "s.toml: [[zones]] file = 'z.geojson'", DataError)
    assert json.dumps(crs)[:60] in str(err.value)


@pytest.mark.parametrize(("crs", "want"), [
    ({"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::32633"}}, "EPSG:32633"),
    ({"type": "EPSG", "properties": {"code": 32633}}, "EPSG:32633"),
    ({"type": "name", "properties": {"name": "urn:ogc:def:crs:OGC:1.3:CRS84"}}, "EPSG:4326"),
    (None, "EPSG:4326"),
    (..., "EPSG:4326"),
])
def test_a_crs_gdal_builds_reads_as_before(tmp_path, crs, want):
    layer = read_vector(_geojson(tmp_path / "z.json", crs), "z", DataError)
    assert layer.crs.equals(CRS.from_user_input(want), ignore_axis_order=True)


_SCENARIO = """
name = "zones crs"
[origin]
lat = -7.0
lon = 70.8
[bounds]
x = [0.0, 5000.0]
y = [-5000.0, 0.0]
z = [-100.0, 0.0]
[mission]
start = [100.0, -100.0, -15.0]
goal = [4500.0, -4500.0, -15.0]
[[zones]]
name = "chart"
file = "z.geojson"
"""

_BOWTIE = [[70.81, -7.01], [70.82, -7.02], [70.82, -7.01], [70.81, -7.02], [70.81, -7.01]]


def test_validate_exits_2_naming_the_file_and_the_crs(tmp_path, capsys):
    (tmp_path / "s.toml").write_text(_SCENARIO)
    _geojson(tmp_path / "z.geojson", {"type": "name", "properties": {"name": "nonsense"}}, _BOWTIE)
    assert main(["validate", str(tmp_path / "s.toml")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "z.geojson': crs {\"type\": \"name\", \"properties\": {\"name\": " \
        "\"nonsense\"}} cannot be built" in err


def test_the_repair_warning_is_shown_on_every_read_with_the_cache_on(tmp_path, monkeypatch, caplog):
    monkeypatch.setenv("AUVPLAN_CACHE", "1")
    monkeypatch.setenv("AUVPLAN_CACHE_DIR", str(tmp_path / "cache"))
    (tmp_path / "s.toml").write_text(_SCENARIO)
    _geojson(tmp_path / "z.geojson", ..., _BOWTIE)
    from auvplan.io.scenario import loader

    for _ in range(3):
        caplog.clear()
        with caplog.at_level(logging.WARNING, logger="auvplan"):
            loader.build(loader.load(str(tmp_path / "s.toml")))
        said = [r.getMessage() for r in caplog.records if "not a valid polygon" in r.getMessage()]
        assert len(said) == 1 and "feature 'A': not a valid polygon (Self-intersection" in said[0]
    assert list((tmp_path / "cache").glob("zones-*.npz"))  # served from the cache after the first read


def test_a_crs_gdal_read_as_another_is_refused(tmp_path):
    """The stated CRS builds, but the layer's CRS differs (GDAL's fallback): refused, naming both."""
    from auvplan.io.data.vector.jsoncrs import check_geojson_crs

    path = _geojson(tmp_path / "z.geojson", {"type": "EPSG", "properties": {"code": 32633}})
    check_geojson_crs(path, "z", DataError, CRS.from_epsg(32633))
    with pytest.raises(DataError, match=r"^z: crs .* is EPSG:32633, but GDAL read the file as EPSG:4326$"):
        check_geojson_crs(path, "z", DataError, CRS.from_epsg(4326))
