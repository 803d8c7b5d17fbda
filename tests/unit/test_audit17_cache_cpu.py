"""Audit 17: the readers' cache keys what a compiled kernel computed (the seabed under an altitude position,
``seabed-at``; a seabed model's nodes) on the CPU it was compiled for.  numba compiles for the host's CPU (or
``NUMBA_CPU_NAME``) with fused multiply-adds where it has them: on this machine the compiled seabed differs from
the same sums in numpy at about half the points, by ulps, so a cache folder shared by two machines served the
first one's bits to the second.  Oracle: the key changes with the CPU numba compiles for, and with nothing else."""

from __future__ import annotations

import pytest

from auvplan.io.data import cache


@pytest.fixture()
def fresh_stamps():
    stamps = [cache.code_stamp, getattr(cache, "host_stamp", None)]
    for f in stamps:
        if f is not None:
            f.cache_clear()
    yield
    for f in stamps:
        if f is not None:
            f.cache_clear()


def _key() -> str:
    for f in (cache.code_stamp, getattr(cache, "host_stamp", None)):
        if f is not None:
            f.cache_clear()
    return cache.request_key("seabed-at", ("grid", ((1.0, 2.0),)), [])


def test_a_cached_compiled_value_is_keyed_on_the_cpu_numba_compiles_for(monkeypatch, fresh_stamps):
    monkeypatch.delenv("NUMBA_CPU_NAME", raising=False)
    monkeypatch.delenv("NUMBA_CPU_FEATURES", raising=False)
    host = _key()
    assert _key() == host  # the same machine: the same entry
    monkeypatch.setenv("NUMBA_CPU_NAME", "generic")  # portable code, no fused multiply-add: other bits
    assert _key() != host
    monkeypatch.delenv("NUMBA_CPU_NAME")
    assert _key() == host


def test_the_host_stamp_names_this_machine_s_processor(fresh_stamps):
    import platform

    stamp = cache.host_stamp()
    assert stamp.startswith(platform.machine())
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as fh:
            flags = next((" ".join(line.split()) for line in fh if line.startswith("flags")), None)
    except OSError:
        flags = None
    if flags is not None:  # the first processor's instruction set (fma, avx512f...) is part of it
        assert flags in stamp.split("\0")
