"""``auvplan serve``: clients that send slowly never hold up anyone else (audit 23; issue #48's "one request never
freezes the page").

A POST's body is read on the event loop, chunk by chunk, before it takes one of the ``WRITER_THREADS`` worker threads
the edits share; a client that stops halfway through its headers or its body holds nothing but its own connection.
More stalled bodies than there are writer threads, and stalled headers, are held open while the page's state is
read and an edit is applied and read back.

Oracle: the invariant (answered, the edit applied); that the stalled bodies really are being read when the other
requests are made is waited for, not slept for: each entry into the body reader is counted.  Planted: the writer
slot taken before the body is read (``async with writers: data = await body(request)``) — the stalled bodies then
hold every slot and this test fails (the fifth stalled body is never read, the edit never answered).
"""

from __future__ import annotations

import socket
import threading

import numpy as np
import pytest

pytest.importorskip("starlette")
pytest.importorskip("uvicorn")
import httpx  # noqa: E402

from auvplan.cli.serve import make_session  # noqa: E402
from auvplan.serve import app as app_mod  # noqa: E402
from auvplan.serve.app import WRITER_THREADS, make_app  # noqa: E402
from serve_helpers import running  # noqa: E402


def test_stalled_headers_and_bodies_hold_up_no_other_request(monkeypatch, tmp_path):
    session = make_session("showcase", [str(tmp_path)])
    stalled = WRITER_THREADS + 2
    entered = threading.Semaphore(0)
    real = app_mod.bounded_body

    async def counted(request, limit):
        entered.release()
        return await real(request, limit)

    monkeypatch.setattr(app_mod, "bounded_body", counted)
    socks: list[socket.socket] = []
    try:
        with running(make_app(session)) as url, httpx.Client(base_url=url, timeout=60) as c:
            host, port = url.removeprefix("http://").split(":")
            for k in range(stalled + 3):
                s = socket.create_connection((host, int(port)))
                socks.append(s)
                if k < stalled:  # a body that stops after 10 of its 100 000 bytes
                    s.sendall(b"POST /api/edit HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
                              b"Content-Length: 100000\r\n\r\n{\"op\": \"mo")
                else:  # headers that stop halfway
                    s.sendall(b"POST /api/edit HTTP/1.1\r\nHost: 127.0.")
            for _ in range(stalled):  # every stalled body is being read (a safety net, not a wait: 60 s)
                assert entered.acquire(timeout=60), "a stalled body was never read: a writer slot held before it"
            state = c.get("/api/state")
            assert state.status_code == 200
            w = np.asarray(state.json()["waypoints"])
            k = len(w) // 2
            e = c.post("/api/edit", json={"op": "move", "index": k, "x": w[k, 0] + 5.0, "y": w[k, 1]})
            assert e.status_code == 200, e.text
            assert np.asarray(c.get("/api/state").json()["waypoints"])[k, 0] == pytest.approx(w[k, 0] + 5.0)
            for s in socks:  # before the server stops (it waits for open connections)
                s.close()
    finally:
        for s in socks:
            s.close()
