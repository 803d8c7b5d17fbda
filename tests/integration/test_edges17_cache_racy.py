"""The readers' cache serves the new bytes of a data file rewritten in place with its size and modification time
kept (``os.utime``, ``cp -p``, ``rsync -t``) within one tick of the file system's clock.

The entry's key holds the file's SHA-256, but a process remembered each file's digest by its device, inode, size,
modification and change times (:data:`auvplan.io.data.cache._DIGESTS`): the change time ticks with a coarse clock
(a few ms on Linux, 2 s on FAT), so a rewrite within the tick kept every time and the old digest — the old data
were read (``serve`` runs for hours).  The tick is simulated (a ``stat`` whose change time stays put) and the
clock is a fake, so the test does not depend on the machine's timing."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from auvplan.io.data import cache

SIZE = 4096


@pytest.fixture
def cache_on(tmp_path, monkeypatch):
    monkeypatch.setenv("AUVPLAN_CACHE", "1")
    monkeypatch.setenv("AUVPLAN_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setattr(cache, "_DIGESTS", {})
    return tmp_path / "cache"


class _Stat:
    """A file's ``stat`` with the change time of the tick it was first written in."""

    def __init__(self, st: os.stat_result, ctime_ns: int) -> None:
        self._st, self.st_ctime_ns = st, ctime_ns

    def __getattr__(self, name: str):  # noqa: ANN204
        return getattr(self._st, name)


def _one_tick(monkeypatch, path: Path) -> int:
    """Every ``stat`` of ``path`` reports the change time it has now; returns it."""
    tick = path.stat().st_ctime_ns
    real = Path.stat

    def stat(self, *, follow_symlinks=True):  # noqa: ANN001, ANN202
        st = real(self, follow_symlinks=follow_symlinks)
        return _Stat(st, tick) if self == path else st

    monkeypatch.setattr(Path, "stat", stat)
    return tick


def _read(path: Path, computed: list[bytes]) -> bytes:
    def compute() -> bytes:
        computed.append(path.read_bytes())
        return computed[-1]

    return cache.cached("probe", ("data.bin",), [path], compute, lambda v: ({"v": np.frombuffer(v, np.uint8)}, {}),
                        lambda a, m: a["v"].tobytes())


def _rewrite_keeping_times(path: Path, data: bytes) -> None:
    st = os.stat(path)
    with open(path, "r+b") as fh:  # in place: the same inode
        fh.write(data)
    os.utime(path, ns=(st.st_atime_ns, st.st_mtime_ns))
    assert os.stat(path).st_size == st.st_size and os.stat(path).st_ino == st.st_ino


def test_a_rewrite_within_one_tick_keeping_size_and_mtime_reads_the_new_bytes(cache_on, tmp_path, monkeypatch):
    path = tmp_path / "data.bin"
    path.write_bytes(b"a" * SIZE)
    tick = _one_tick(monkeypatch, path)
    monkeypatch.setattr(cache, "_now_ns", lambda: tick + 500_000_000)  # read 0.5 s after the write
    computed: list[bytes] = []
    assert _read(path, computed) == b"a" * SIZE
    _rewrite_keeping_times(path, b"b" * SIZE)
    assert _read(path, computed) == b"b" * SIZE  # the old code served b"a" * SIZE from the cache
    assert computed == [b"a" * SIZE, b"b" * SIZE]
    assert _read(path, computed) == b"b" * SIZE and len(computed) == 2  # and the new bytes are a hit


def test_an_old_file_is_hashed_once(cache_on, tmp_path, monkeypatch):
    """The digest is still remembered for a file whose times are past the racy window (an ensemble file's members
    are one hash): oracle, the digests counted."""
    path = tmp_path / "data.bin"
    path.write_bytes(b"a" * SIZE)
    tick = _one_tick(monkeypatch, path)
    monkeypatch.setattr(cache, "_now_ns", lambda: tick + cache._RACY_NS + 1)
    counted: list[Path] = []
    real = cache._digest
    monkeypatch.setattr(cache, "_digest", lambda p: counted.append(p) or real(p))
    computed: list[bytes] = []
    for _ in range(3):
        assert _read(path, computed) == b"a" * SIZE
    assert len(counted) == 1 and len(computed) == 1
