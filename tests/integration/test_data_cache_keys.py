"""The readers' cache (:mod:`auvplan.io.data.cache`) under what the first tests of it never varied: an entry
damaged anywhere (cut short at any length, any byte flipped), a GeoTIFF whose georeferencing a sidecar file
changes, and two links to one file read with the same request."""

from __future__ import annotations

import logging
import os
from pathlib import Path

import numpy as np
import pytest

from auvplan.io.data import cache
from auvplan.io.data.bathymetry import TerrainSpec, load_terrain
from auvplan.io.data.geo import LocalFrame


@pytest.fixture
def cache_on(tmp_path, monkeypatch):
    monkeypatch.setenv("AUVPLAN_CACHE", "1")
    monkeypatch.setenv("AUVPLAN_CACHE_DIR", str(tmp_path / "cache"))
    return tmp_path / "cache"


def test_an_entry_damaged_anywhere_is_recomputed_never_raised(cache_on, tmp_path):
    """Oracle: the computed value.  The entry cut short (a copy interrupted) at every 29th length, and a byte
    flipped (a bad sector) at every 7th offset and at each of the zip directory's (a flipped member name still
    unzips, without ``v``; a flipped version is a ``NotImplementedError`` of zipfile): the call
    returns the value, never raises (``BadZipFile``, ``NotImplementedError``, ``KeyError`` before), and the
    entry is replaced (the next call is a hit)."""
    src = tmp_path / "data.bin"
    src.write_bytes(b"some data")
    calls: list[int] = []

    def compute() -> np.ndarray:
        calls.append(1)
        return np.arange(6.0)

    def run() -> np.ndarray:
        return cache.cached("probe", ("a", 0.1), [src], compute, lambda v: ({"v": v}, {"n": int(v.size)}),
                            lambda a, m: a["v"][: m["n"]])

    run()
    entry = next(cache_on.glob("*.npz"))
    good = entry.read_bytes()
    n = len(good)
    cut = [good[:k] for k in range(0, n, 29)]
    offsets = [*range(0, n - 150, 7), *range(n - 150, n)]  # every byte of the zip's directory, at its end
    flipped = [good[:j] + bytes([good[j] ^ 0x55]) + good[j + 1:] for j in offsets]
    for bad in cut + flipped:
        entry.write_bytes(bad)
        before = len(calls)
        assert np.array_equal(run(), np.arange(6.0))
        assert len(calls) == before + 1 or bad in flipped  # a cut entry is always recomputed (a flip in bytes
        # unzipping ignores, a timestamp, is served as it is: its arrays and record pass the zip's CRC)
    entry.write_bytes(good[:-1])
    run()
    before = len(calls)
    assert np.array_equal(run(), np.arange(6.0)) and len(calls) == before  # replaced: a hit again


def _tif(folder: Path) -> Path:
    import rioxarray  # noqa: F401
    import xarray as xr

    x = 158.8 + 0.01 * np.arange(20)
    y = (15.0 + 0.01 * np.arange(20))[::-1]
    z = -2000.0 + 1000.0 * (x[None, :] - 158.8) + 0.0 * y[:, None]  # 10 m deeper per 0.01 deg west
    da = xr.DataArray(z.astype("float32"), dims=("y", "x"), coords={"y": y, "x": x}).rio.write_crs("EPSG:4326")
    path = folder / "g.tif"
    da.rio.to_raster(path)
    return path


def test_a_geotiff_sidecar_edit_is_a_new_entry(cache_on, tmp_path, monkeypatch):
    """GDAL takes a GeoTIFF's georeferencing from ``g.tif.aux.xml`` when there is one (QGIS writes it when a
    raster is georeferenced again): with one added that moves the raster 0.05 deg west, the seabed read is
    the moved one (oracle: the cache off), not the entry of the file alone; the 0.05 deg shift makes the
    seabed 50 m shallower on average (the relief's slope)."""
    import rasterio

    path = _tif(tmp_path)
    spec, frame, extent = TerrainSpec(file=str(path), method="linear"), LocalFrame(15.1, 158.9), (-3e3, 3e3, -3e3, 3e3)
    before = load_terrain(spec, frame, extent_m=extent)
    with rasterio.open(path) as src:
        gt = list(src.transform.to_gdal())
    gt[0] -= 0.05
    (tmp_path / "g.tif.aux.xml").write_text(f"<PAMDataset><GeoTransform>{', '.join(map(repr, gt))}</GeoTransform>"
                                            "</PAMDataset>")
    after = load_terrain(spec, frame, extent_m=extent)
    monkeypatch.setenv("AUVPLAN_CACHE", "0")
    oracle = load_terrain(spec, frame, extent_m=extent)
    assert np.array_equal(after.z, oracle.z)
    assert np.mean(after.z) - np.mean(before.z) == pytest.approx(50.0, abs=1.0)
    assert len(list(cache_on.glob("terrain-*.npz"))) == 2


def test_two_links_to_one_file_replay_their_own_names(cache_on, tmp_path, caplog):
    """Two scenario folders whose ``cur.nc`` links to one download, read with the same request: each hit
    replays the log lines of its own path (a reader names the path it was given; oracle: that path)."""
    target = tmp_path / "download.nc"
    target.write_bytes(b"the same bytes")
    links = []
    for folder in ("s1", "s2"):
        (tmp_path / folder).mkdir()
        (tmp_path / folder / "cur.nc").symlink_to(target)
        links.append(tmp_path / folder / "cur.nc")

    def read(path: Path) -> float:
        def compute() -> float:
            logging.getLogger("auvplan.io.data.test").warning("%s: 3 gaps filled", path)
            return 1.0

        return cache.cached("probe", ("cur.nc",), [path], compute, lambda v: ({"v": np.asarray(v)}, {}),
                            lambda a, m: float(a["v"]))

    for path in links + links:  # computed for each, then a hit for each
        caplog.clear()
        with caplog.at_level(logging.WARNING, logger="auvplan"):
            assert read(path) == 1.0
        assert [r.getMessage() for r in caplog.records] == [f"{path}: 3 gaps filled"]


def test_a_file_read_again_unchanged_is_hashed_once_an_edit_again(cache_on, tmp_path, monkeypatch):
    """Each member of an ensemble file is one read through the cache (``read_currents(member=…)``): the file was
    hashed whole for every member (50 members of a 1 GB file: 50 GB hashed on a warm run).  Oracle: the digests
    counted — one for the unchanged file whatever the requests, one more after each edit, even one that keeps
    the size and the modification time (the change time moves), and the key then changes."""
    path = tmp_path / "ens.nc"
    path.write_bytes(b"member data " * 1000)
    path.touch()
    counted: list[Path] = []
    real = cache._digest
    monkeypatch.setattr(cache, "_digest", lambda p: counted.append(p) or real(p))
    clock = cache._now_ns
    monkeypatch.setattr(cache, "_now_ns", lambda: clock() + 10 * 10**9)  # read 10 s after its write: not racy
    keys = [cache.request_key("currents", ("ens.nc", ("member", j)), [path]) for j in range(5)]
    assert len(set(keys)) == 5 and len(counted) == 1
    monkeypatch.setattr(cache, "_now_ns", clock)  # the edit is read at once (tests/.../test_edges17_cache_racy.py)
    st = path.stat()
    path.write_bytes(b"MEMBER DATA " * 1000)  # same size ...
    os.utime(path, ns=(st.st_atime_ns, st.st_mtime_ns))  # ... and modification time
    assert cache.request_key("currents", ("ens.nc", ("member", 0)), [path]) != keys[0] and len(counted) == 2
