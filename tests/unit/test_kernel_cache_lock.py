"""Two processes compiling one kernel at once (the suite and tests/warm_kernels.py beside it on CI, two dask
workers on a fresh install), or one killed as it writes: numba writes a kernel's index, then the data file it
names, each atomically but not the pair.  A reader between the two (or any reader after a kill between them)
read the new index and the data file of that number an older source left (numbered files are reused after an
edit): the old machine code.  auvplan writes the data file first, then the index, and reads and writes them
under one lock of the index (:func:`auvplan.runtime.jit._locked_file_class`)."""

from __future__ import annotations

import threading

import pytest

from auvplan.runtime.jit import _locked_file_class


def _entry(folder, stamp: str):
    return _locked_file_class()(cache_path=str(folder), filename_base="kernel-12.py311", source_stamp=stamp)


def test_a_kernel_s_cache_entry_is_never_read_while_it_is_written(tmp_path):
    _entry(tmp_path, "the source before an edit").save("sig", b"old machine code")  # its index and data file 1
    writer, reader = _entry(tmp_path, "the source now"), _entry(tmp_path, "the source now")
    writing, go = threading.Event(), threading.Event()
    real = writer._save_data

    def paused(name, data):  # the writer in the middle of its entry
        writing.set()
        assert go.wait(60)
        real(name, data)

    writer._save_data = paused
    w = threading.Thread(target=writer.save, args=("sig", b"new machine code"), daemon=True)
    w.start()
    assert writing.wait(60)
    got: dict[str, object] = {}
    r = threading.Thread(target=lambda: got.setdefault("code", reader.load("sig")), daemon=True)
    r.start()
    r.join(0.5)
    waited = r.is_alive()  # the reader waits for the writer as long as it writes (the 0.5 s only gives a bug time)
    go.set()
    w.join(60)
    r.join(60)
    assert waited and got["code"] == b"new machine code", got


def test_a_kill_while_a_kernel_is_written_never_leaves_old_machine_code_named(tmp_path):
    _entry(tmp_path, "the source before an edit").save("sig", b"old machine code")
    killed = _entry(tmp_path, "the source now")

    def dies(name, data):  # the process is killed as it writes the data file
        raise KeyboardInterrupt

    killed._save_data = dies
    with pytest.raises(KeyboardInterrupt):
        killed.save("sig", b"new machine code")
    assert _entry(tmp_path, "the source now").load("sig") is None  # compiled again, never the old code
    again = _entry(tmp_path, "the source now")
    again.save("sig", b"new machine code")
    assert _entry(tmp_path, "the source now").load("sig") == b"new machine code"
