"""Coastlines and charted zones kept in the readers' cache (:mod:`auvplan.io.data.vector.kept`, issue 56): a hit is
the fresh read vertex for vertex, no vector file is opened for it, and editing any file of the data set (a
shapefile's ``.dbf`` beside an unchanged ``.shp``) reads it again."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pyogrio
import pytest
import shapely

from auvplan.io.data import cache
from auvplan.io.data.geo import LocalFrame
from auvplan.io.data.vector import coast
from auvplan.io.data.vector import zones as zones_io
from auvplan.io.data.vector.coast import LandSpec, read_land
from auvplan.io.data.vector.zones import ZoneSpec

JDF = LocalFrame(48.15, -122.75)  # admiralty-inlet's origin
REEFS = Path(coast.__file__).resolve().parents[3] / "data" / "ne_10m_reefs_chagos.geojson"


@pytest.fixture
def cache_on(tmp_path, monkeypatch):
    monkeypatch.setenv("AUVPLAN_CACHE", "1")
    monkeypatch.setenv("AUVPLAN_CACHE_DIR", str(tmp_path / "cache"))
    return tmp_path / "cache"


def _no_reader(*args, **kwargs):
    raise AssertionError("a kept result must not open the vector file")


def _land():
    return read_land(LandSpec(builtin="gshhg-juan-de-fuca"), JDF, (-8000.0, 8000.0, -6000.0, 9000.0)).geometry


def _reefs() -> list[tuple[str, bytes]]:
    """The named local-frame features of Natural Earth's reefs (what read_zones buffers into footprints)."""
    spec = ZoneSpec(where_="s.toml: [[zones]] #1", name="reef", kind="file", buffer_m=2000.0, file=str(REEFS))
    named = zones_io._read_file(spec, LocalFrame(-5.5, 72.0), None, shapely.box(-60e3, -40e3, 60e3, 40e3))
    return [(name, shapely.to_wkb(g)) for name, g in named]


def test_a_kept_coastline_is_the_fresh_one_vertex_for_vertex(cache_on, monkeypatch):
    """Oracle: the reader with the cache off (WKB bytes equal: every float64 the same)."""
    monkeypatch.setenv("AUVPLAN_CACHE", "0")
    fresh = _land()
    monkeypatch.setenv("AUVPLAN_CACHE", "1")
    first = _land()
    assert len(list(cache_on.glob("land-*.npz"))) == 1
    monkeypatch.setattr(coast, "read_vector", _no_reader)
    again = _land()
    assert not fresh.is_empty and shapely.to_wkb(again) == shapely.to_wkb(first) == shapely.to_wkb(fresh)


def test_kept_zones_are_the_fresh_ones_with_their_names(cache_on, monkeypatch):
    """Oracle: the cache off; Natural Earth's reef lines in the local frame, names and vertices equal."""
    monkeypatch.setenv("AUVPLAN_CACHE", "0")
    fresh = _reefs()
    monkeypatch.setenv("AUVPLAN_CACHE", "1")
    assert _reefs() == fresh
    monkeypatch.setattr(zones_io, "read_vector", _no_reader)
    assert len(fresh) >= 2 and _reefs() == fresh


def test_an_edited_sidecar_file_is_read_again(cache_on, tmp_path):
    """A shapefile rewritten with the same polygon and another name: the ``.shp`` keeps its bytes, the ``.dbf``
    changes, and the zone's name follows the new file (a key on the ``.shp`` alone would serve the old one)."""
    poly = shapely.box(-76.45, 38.75, -76.35, 38.85)
    path = tmp_path / "areas.shp"

    def write(name: str) -> None:
        pyogrio.raw.write(path, np.array([shapely.to_wkb(poly)], dtype=object), [np.array([name], dtype=object)],
                          ["OBJNAM"], driver="ESRI Shapefile", crs="EPSG:4326", geometry_type="Polygon")

    def names() -> list[str]:
        spec = ZoneSpec(where_="s.toml: [[zones]] #1", name="c", kind="file", file=str(path))
        box = shapely.box(-9e3, -9e3, 9e3, 9e3)
        return [n for n, _ in zones_io._read_file(spec, LocalFrame(38.8, -76.4), None, box)]

    write("Old Range")
    shp = path.read_bytes()
    assert names() == ["c: Old Range"]
    write("New Range")
    assert path.read_bytes() == shp and {p.suffix for p in cache.dataset_files(path)} >= {".shp", ".dbf", ".prj"}
    assert names() == ["c: New Range"]
    assert len(list(cache_on.glob("zones-*.npz"))) == 2
