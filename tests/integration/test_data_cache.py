"""The readers' on-disk cache (:mod:`auvplan.io.data.cache`): a hit gives the very arrays a fresh read gives, and
an entry is never served once anything it was made from changed (the file's bytes, even with its size and time
kept; its time alone; the request; the memory budget; the code)."""

from __future__ import annotations

import json
import logging
import os
import shutil
import subprocess
import sys
from pathlib import Path

import netCDF4
import numpy as np
import pytest

from auvplan.io.data import cache
from auvplan.io.data.bathymetry import TerrainSpec, builtin_terrain_path, load_terrain
from auvplan.io.data.geo import LocalFrame
from auvplan.io.data.ocean.currents import CurrentsFileSpec, read_currents
from auvplan.io.files import limits

DATA = Path(builtin_terrain_path("etopo1-chagos")).parent
CHAGOS = LocalFrame(-6.0, 71.8)


@pytest.fixture
def cache_on(tmp_path, monkeypatch):
    """The cache on, in a folder of the test's own."""
    monkeypatch.setenv("AUVPLAN_CACHE", "1")
    monkeypatch.setenv("AUVPLAN_CACHE_DIR", str(tmp_path / "cache"))
    return tmp_path / "cache"


def _entries(folder: Path) -> list[Path]:
    return sorted(folder.glob("*.npz")) if folder.is_dir() else []


def _terrain(path: Path, extent=(-20e3, 20e3, -20e3, 20e3)):
    return load_terrain(TerrainSpec(file=str(path), resample_m=2000.0), CHAGOS, extent_m=extent)


def _same_terrain(a, b) -> None:
    for k in ("x", "y", "z"):
        assert np.array_equal(getattr(a, k), getattr(b, k)), k
    assert (a.name, a.fit) == (b.name, b.fit)


def test_a_hit_is_the_fresh_read_bit_for_bit(cache_on, monkeypatch):
    """Oracle: the reader with the cache off.  The second call is served from the one entry (the reader is not
    run: its regridding is replaced by one that fails)."""
    monkeypatch.setenv("AUVPLAN_CACHE", "0")
    fresh = _terrain(DATA / "etopo1_chagos.nc")
    monkeypatch.setenv("AUVPLAN_CACHE", "1")
    first = _terrain(DATA / "etopo1_chagos.nc")
    assert len(_entries(cache_on)) == 1
    import auvplan.io.data.bathymetry as bathy

    monkeypatch.setattr(bathy, "read_bathymetry", lambda *a, **k: pytest.fail("read again on a hit"))
    again = _terrain(DATA / "etopo1_chagos.nc")
    _same_terrain(fresh, first)
    _same_terrain(fresh, again)
    assert fresh.fit is not None and fresh.fit.method == "conservative"


def test_a_changed_file_is_never_served_from_the_cache(cache_on, tmp_path):
    """The file's values changed with its size and modification time kept: the new seabed, not the old one
    (oracle: the edited file read with the cache off); its time alone changed: a new entry."""
    path = tmp_path / "grid.nc"
    shutil.copy(DATA / "etopo1_chagos.nc", path)
    before = _terrain(path)
    st = path.stat()
    with netCDF4.Dataset(path, "r+") as nc:
        name = next(n for n, v in nc.variables.items() if v.ndim == 2)
        nc.variables[name][:] = nc.variables[name][:] - 100.0  # 100 m deeper everywhere
    assert path.stat().st_size == st.st_size
    os.utime(path, ns=(st.st_atime_ns, st.st_mtime_ns))
    after = _terrain(path)
    os.environ["AUVPLAN_CACHE"] = "0"
    try:
        oracle = _terrain(path)
    finally:
        os.environ["AUVPLAN_CACHE"] = "1"
    _same_terrain(after, oracle)
    assert np.allclose(after.z, before.z - 100.0, atol=1e-6)
    n = len(_entries(cache_on))
    os.utime(path, ns=(st.st_atime_ns, st.st_mtime_ns + 10**9))  # touched: the same bytes, a new key
    _same_terrain(_terrain(path), oracle)
    assert len(_entries(cache_on)) == n + 1


def test_the_request_the_budget_and_the_code_are_in_the_key(cache_on, monkeypatch):
    path = DATA / "etopo1_chagos.nc"
    a = _terrain(path)
    b = _terrain(path, extent=(-10e3, 10e3, -10e3, 10e3))  # another extent: another seabed
    assert b.x[-1] == pytest.approx(10e3) and a.x[-1] == pytest.approx(20e3)
    with limits.budget(limits.Limits(memory_mb=512.0)):  # the budget is part of a reader's verdict
        _terrain(path)
    monkeypatch.setattr(cache, "code_stamp", lambda: "an edited auvplan")
    _terrain(path)
    assert len(_entries(cache_on)) == 4


def test_a_current_file_regridded_once_and_read_back_identical(cache_on, monkeypatch):
    """NorKyst-800 (polar stereographic, turned to east/north): the cached field is the fresh one."""
    from pyproj import CRS, Transformer

    spec = CurrentsFileSpec(str(DATA / "norkyst800_stere_cut.nc"))
    with netCDF4.Dataset(spec.path) as nc:  # the local frame about the file's own centre
        crs = CRS.from_cf(nc.variables["projection_stere"].__dict__)
        x, y = float(np.mean(nc.variables["X"][:])), float(np.mean(nc.variables["Y"][:]))
    lon, lat = Transformer.from_crs(crs, "EPSG:4326", always_xy=True).transform(x, y)
    frame = LocalFrame(float(lat), float(lon))
    monkeypatch.setenv("AUVPLAN_CACHE", "0")
    fresh = read_currents(spec, frame, extent_m=(-5e3, 5e3, -5e3, 5e3))
    monkeypatch.setenv("AUVPLAN_CACHE", "1")
    first = read_currents(spec, frame, extent_m=(-5e3, 5e3, -5e3, 5e3))
    again = read_currents(spec, frame, extent_m=(-5e3, 5e3, -5e3, 5e3))
    assert len(_entries(cache_on)) == 1
    for c in (first, again):
        for k in ("x", "y", "z", "u", "v", "w", "t"):
            want, got = getattr(fresh, k), getattr(c, k)
            assert (want is None and got is None) or np.array_equal(np.asarray(want), np.asarray(got)), k
        assert c.name == fresh.name
        pts = np.array([[0.0, 0.0, -5.0], [3e3, -2e3, -20.0]])
        assert np.array_equal(c.velocity(pts, 3600.0), fresh.velocity(pts, 3600.0))


def test_log_records_replayed_damaged_entries_recomputed_errors_not_kept(cache_on, caplog):
    calls = []

    def compute():
        calls.append(1)
        logging.getLogger("auvplan.io.data.test").warning("filled %d gaps", 3)
        logging.getLogger("auvplan.io.data.test").info("an info line")
        return np.arange(4.0)

    def run():
        return cache.cached("probe", ("a", 1.5), [DATA / "etopo1_chagos.nc"], compute,
                            lambda v: ({"v": v}, {"n": int(v.size)}), lambda arr, meta: arr["v"][: meta["n"]])

    with caplog.at_level(logging.WARNING, logger="auvplan"):
        first = run()
        second = run()
    assert calls == [1] and np.array_equal(first, second)
    assert [r.getMessage() for r in caplog.records] == ["filled 3 gaps"] * 2  # INFO kept but not shown
    caplog.clear()
    with caplog.at_level(logging.INFO, logger="auvplan"):
        run()
    assert [r.getMessage() for r in caplog.records] == ["filled 3 gaps", "an info line"]  # shown at -v
    entry = _entries(cache_on)[0]
    entry.write_bytes(b"not an npz")
    assert np.array_equal(run(), first) and calls == [1, 1]  # damaged: recomputed and replaced
    assert np.array_equal(run(), first) and calls == [1, 1]

    def fails():
        calls.append(2)
        raise ValueError("unreadable")

    for _ in range(2):
        with pytest.raises(ValueError):
            cache.cached("fails", (), [DATA / "etopo1_chagos.nc"], fails, lambda v: ({}, {}), lambda a, m: None)
    assert calls.count(2) == 2


def test_a_warm_validate_reads_no_netcdf_stack(cache_on):
    """The front door (issue 56): once a scenario's files are cached, ``validate`` of chagos-reefs (an ETOPO1
    cut-out, Natural Earth's reef lines as zones) imports none of the NetCDF or vector readers' stack (xarray,
    netCDF4, dask, pandas, pyogrio), and the swarm's B-spline basis no scipy.interpolate (a fresh interpreter's
    modules, not a clock; a kept coastline opens no file either: test_kept_vectors.py)."""
    stack = ("xarray", "netCDF4", "dask", "pandas", "pyogrio", "scipy.interpolate", "scipy.stats", "matplotlib")
    probe = ("import contextlib, io, json, sys\nfrom auvplan.cli import main\n"
             "with contextlib.redirect_stdout(io.StringIO()):\n    code = main(['validate', 'chagos-reefs'])\n"
             "from auvplan.path.curves import basis_matrix\nbasis_matrix(9, 200, 1)\n"
             f"print(json.dumps([code, sorted(m for m in {stack!r} if m in sys.modules)]))")

    def modules(enabled: str) -> list:
        env = {**os.environ, "AUVPLAN_CACHE": enabled}
        out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True, env=env)
        return json.loads(out.stdout.strip().splitlines()[-1])

    code, first = modules("1")  # the first run reads
    assert code == 0 and {"xarray", "netCDF4", "pyogrio", "pandas"} <= set(first), first
    assert modules("1") == [0, []]  # (with the cache off: tests/integration/test_front_door.py)


def test_a_reader_inside_a_reader_and_another_threads_records(cache_on, caplog):
    """An inner reader's warning is kept once in the outer entry; a record another thread logs meanwhile is
    shown as it comes and is not kept; the logger's level and propagation are restored."""
    import threading

    log = logging.getLogger("auvplan.io.data.test")
    src = [DATA / "etopo1_chagos.nc"]
    pack, unpack = (lambda v: ({"v": np.asarray(v)}, {})), (lambda a, m: float(a["v"]))

    def inner():
        log.warning("inner")
        return 1.0

    def outer():
        t = threading.Thread(target=lambda: log.warning("other thread"))
        t.start()
        t.join()
        log.warning("outer")
        return cache.cached("inner", (), src, inner, pack, unpack) + 1.0

    def run():
        return cache.cached("outer", (), src, outer, pack, unpack)

    with caplog.at_level(logging.WARNING, logger="auvplan"):
        assert run() == 2.0
        shown = [r.getMessage() for r in caplog.records]
        caplog.clear()
        assert run() == 2.0
        replayed = [r.getMessage() for r in caplog.records]
    assert shown.count("other thread") == 1 and shown.count("inner") == 1 and shown.count("outer") == 1
    assert replayed == ["outer", "inner"]
    root = logging.getLogger("auvplan")
    assert root.propagate and not [h for h in root.handlers if type(h).__name__ == "_Tape"]
