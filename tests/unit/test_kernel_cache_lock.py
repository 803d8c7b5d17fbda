"""Two processes compiling one kernel at once (the suite and tests/warm_kernels.py beside it on CI, two dask
workers on a fresh install): numba writes a kernel's index, then the data file it names, each atomically but
not the pair.  A reader between the two read the new index and the data file of that number an older source
left (numbered files are reused after an edit): the old machine code.  auvplan reads and writes them under one
lock of the index (:func:`auvplan.runtime.jit._locked_file_class`)."""

from __future__ import annotations

import threading

from auvplan.runtime.jit import _locked_file_class


def test_a_kernel_s_cache_entry_is_never_read_between_its_index_and_its_data(tmp_path):
    files = _locked_file_class()

    def entry(stamp: str):
        return files(cache_path=str(tmp_path), filename_base="kernel-12.py311", source_stamp=stamp)

    entry("the source before an edit").save("sig", b"old machine code")  # its index and data file 1
    writer, reader = entry("the source now"), entry("the source now")
    indexed, go = threading.Event(), threading.Event()
    real = writer._save_data

    def paused(name, data):  # the writer between its index (written: the new source's, naming file 1) and file 1
        indexed.set()
        assert go.wait(60)
        real(name, data)

    writer._save_data = paused
    w = threading.Thread(target=writer.save, args=("sig", b"new machine code"), daemon=True)
    w.start()
    assert indexed.wait(60)
    got: dict[str, object] = {}
    r = threading.Thread(target=lambda: got.setdefault("code", reader.load("sig")), daemon=True)
    r.start()
    r.join(0.5)
    waited = r.is_alive()  # the reader waits for the writer as long as it writes (the 0.5 s only gives a bug time)
    go.set()
    w.join(60)
    r.join(60)
    assert waited and got["code"] == b"new machine code", got
