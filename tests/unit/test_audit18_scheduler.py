"""audit18: ``--scheduler`` at an address that accepts the TCP connection but never answers (another service on
the port, a proxy, a stopped process's socket) is given up after the connect timeout too.

dask's ``connect`` bounds the TCP connection by its timeout but then waits for the scheduler's handshake without
one: ``Runner.map`` hung for good (over 120 s seen; the 5 s bound of wave 17 held only where nothing accepts).
An address that answers something else (an HTTP server: the dashboard's port 8787 given for the scheduler's)
was read as a frame of 3 EiB: a ``MemoryError`` traceback.  Oracle: a local socket that accepts and stays silent,
or answers HTTP; the error within a few timeouts, one line naming the flag."""

from __future__ import annotations

import socket
import threading
import time

import pytest


@pytest.mark.parametrize("answer", [b"", b"HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n"],
                         ids=["silent", "http"])
def test_an_address_that_accepts_but_is_no_scheduler_is_given_up(answer: bytes) -> None:
    dask = pytest.importorskip("dask")
    pytest.importorskip("distributed")
    from auvplan.errors import AuvplanError
    from auvplan.runtime.parallel import Runner

    srv = socket.socket()
    srv.bind(("127.0.0.1", 0))
    srv.listen(8)
    held: list[socket.socket] = []

    def accept() -> None:
        while True:
            try:
                held.append(srv.accept()[0])  # kept open
                if answer:
                    held[-1].sendall(answer)
            except OSError:
                return

    threading.Thread(target=accept, daemon=True).start()
    address = f"tcp://127.0.0.1:{srv.getsockname()[1]}"
    box: dict[str, object] = {}

    def run() -> None:
        try:
            Runner(scheduler=address).map(abs, [1, 2])
        except Exception as exc:  # noqa: BLE001 - the test reads what was raised
            box["exc"] = exc

    t0 = time.monotonic()
    with dask.config.set({"distributed.comm.timeouts.connect": "0.3s"}):
        worker = threading.Thread(target=run, daemon=True)  # a hang fails the test instead of stalling the suite
        worker.start()
        worker.join(20.0)
    try:
        assert not worker.is_alive(), "Runner.map still waiting at the address after 20 s"
        assert isinstance(box.get("exc"), AuvplanError), box
        assert str(box["exc"]).startswith(f"--scheduler {address!r}: no dask scheduler reached there within 0.3 s")
        assert time.monotonic() - t0 < 10.0
    finally:
        srv.close()
        for c in held:
            c.close()
