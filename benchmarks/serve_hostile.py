"""``auvplan serve`` under hostile requests (issue 48): answer latency of another request, and memory.

Starts ``auvplan serve showcase --no-browser`` as its own process on a free port of 127.0.0.1 and, while
a prober asks ``GET /api/state`` every 50 ms, sends one hostile request at a time:

* a waypoint inserted 10⁹ m away, ``[endurance] ds_m = 1e-9``, a survey of the whole chart (the
  estimator's refusals), a re-plan and a flight (long work, run aside), a second re-plan while the
  first runs (``busy``), an edit while a re-plan runs (the plan is dropped: ``superseded``);
* a 300 MB body (declared, and streamed in chunks without a length), the server's resident memory
  (``VmRSS`` of its process, sampled every 20 ms) before and at its peak;
* 600 concurrent ``POST /api/check`` from 600 connections, the peak memory and how many were answered.

Prints one table (the worst probe latency during each request, its status and the memory figures);
``--figure`` writes it to ``docs/figures/serve-hostile.md`` (quoted in docs/serve.md).

    python benchmarks/serve_hostile.py [--figure]
"""

from __future__ import annotations

import argparse
import http.client
import json
import os
import socket
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024.0
    return float("nan")


class Peak:
    """The largest RSS of a process while the ``with`` block runs (sampled every 20 ms)."""

    def __init__(self, pid: int) -> None:
        self.pid, self.peak, self._stop = pid, 0.0, threading.Event()

    def __enter__(self) -> Peak:
        self.peak = _rss_mb(self.pid)
        self._t = threading.Thread(target=self._run, daemon=True)
        self._t.start()
        return self

    def _run(self) -> None:
        while not self._stop.wait(0.02):
            self.peak = max(self.peak, _rss_mb(self.pid))

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        self._t.join()


class Prober:
    """``GET /api/state`` every 50 ms from its own connection; the worst latency of a window."""

    def __init__(self, port: int) -> None:
        self.port, self.samples, self._stop = port, [], threading.Event()
        self._t = threading.Thread(target=self._run, daemon=True)
        self._t.start()

    def _run(self) -> None:
        while not self._stop.is_set():
            t0 = time.perf_counter()
            try:
                c = http.client.HTTPConnection("127.0.0.1", self.port, timeout=60)
                c.request("GET", "/api/state")
                ok = c.getresponse().status == 200
                c.close()
            except OSError:
                ok = False
            t1 = time.perf_counter()
            self.samples.append((t0, t1 - t0, ok))
            time.sleep(0.05)

    def worst(self, t0: float, t1: float) -> tuple[float, int]:
        lat = [d for (t, d, ok) in self.samples if t0 <= t <= t1 or (t < t0 and t + d > t0)]
        return (max(lat) if lat else float("nan")), len(lat)

    def stop(self) -> None:
        self._stop.set()
        self._t.join()


def _latency(prober: Prober, t1: float, t2: float) -> str:
    worst, n = prober.worst(t1, t2)
    if n == 0:
        return f"answered in {1000 * (t2 - t1):.0f} ms (no probe fell inside)"
    return f"{1000 * worst:.0f} ms over {n} probes (request {t2 - t1:.1f} s)"


def _post(port: int, path: str, data: object, timeout: float = 600) -> tuple[int, dict]:
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=timeout)
    body = json.dumps(data).encode()
    c.request("POST", path, body=body, headers={"Content-Type": "application/json"})
    r = c.getresponse()
    out = r.read()
    c.close()
    try:
        return r.status, json.loads(out)
    except ValueError:
        return r.status, {}


def _state(port: int) -> dict:
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
    c.request("GET", "/api/state")
    out = json.loads(c.getresponse().read())
    c.close()
    return out


def _big_body(port: int, mb: int, declared: bool) -> tuple[int, float]:
    """Send ``mb`` MB of JSON-looking bytes to /api/edit; the status (0 when the server cut us off) and seconds."""
    chunk = b"[" + b"1," * (512 * 1024 - 1)
    n = mb * 1024 * 1024 // len(chunk)
    s = socket.create_connection(("127.0.0.1", port), timeout=120)
    head = ("POST /api/edit HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
            + (f"Content-Length: {n * len(chunk)}\r\n" if declared else "Transfer-Encoding: chunked\r\n") + "\r\n")
    t0 = time.perf_counter()
    status = 0
    try:
        s.sendall(head.encode())
        for _ in range(n):
            s.sendall(chunk if declared else f"{len(chunk):x}\r\n".encode() + chunk + b"\r\n")
        if not declared:
            s.sendall(b"0\r\n\r\n")
    except OSError:
        pass  # the server answered and closed: the rest of the body is never read
    try:
        s.settimeout(30)
        line = s.recv(4096).split(b"\r\n", 1)[0].split()
        status = int(line[1]) if len(line) > 1 else 0
    except OSError:
        pass
    s.close()
    return status, time.perf_counter() - t0


def _concurrent_checks(port: int, n: int) -> tuple[int, int]:
    """``n`` POST /api/check at once (each its own connection); how many got 200 and how many any answer."""
    barrier = threading.Barrier(n)

    def one(i: int) -> int:
        c = http.client.HTTPConnection("127.0.0.1", port, timeout=600)
        c.connect()
        barrier.wait()
        try:
            c.request("POST", "/api/check", body=json.dumps({"semantics": "held", "pitch": 15.0 + i % 3}),
                      headers={"Content-Type": "application/json"})
            st = c.getresponse().status
        except OSError:
            st = 0
        c.close()
        return st

    with ThreadPoolExecutor(n) as ex:
        codes = list(ex.map(one, range(n)))
    return sum(c == 200 for c in codes), sum(c != 0 for c in codes)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--figure", action="store_true", help="write docs/figures/serve-hostile.md")
    args = ap.parse_args(argv)
    port = _free_port()
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    log = open(Path(os.environ.get("TMPDIR", "/tmp")) / f"serve-hostile-{port}.log", "w+")
    server = subprocess.Popen([sys.executable, "-m", "auvplan", "serve", "showcase", "--port", str(port),
                               "--no-browser"], stdout=log, stderr=log, env=env, cwd=ROOT)
    rows: list[tuple[str, str, str]] = []
    try:
        t0 = time.monotonic()
        while True:
            try:
                _state(port)
                break
            except OSError:
                if time.monotonic() - t0 > 300 or server.poll() is not None:
                    raise RuntimeError("the server did not start") from None
                time.sleep(0.2)
        idle = _rss_mb(server.pid)
        prober = Prober(port)
        time.sleep(0.5)
        far = {"op": "insert", "x": 1e9, "y": 1e9}
        cases = [
            ("insert a waypoint 10⁹ m away", "/api/edit", far),
            ("[endurance] ds_m = 1e-9", "/api/set", {"table": "endurance", "key": "ds_m", "value": 1e-9}),
            ("survey a 10⁶-point polygon", "/api/survey", {"polygon": [[float(i % 1000), float(i // 1000)]
                                                                       for i in range(1_000_000)]}),
            ("survey a polygon 10⁹ m wide", "/api/survey", {"polygon": [[-1e9, -1e9], [1e9, -1e9], [1e9, 1e9]]}),
            ("re-plan (long work, aside)", "/api/plan", {"planner": "iabc", "seed": 1}),
            ("fly the mission (long work, aside)", "/api/fly", {}),
        ]
        for name, path, data in cases:
            t1 = time.perf_counter()
            code, out = _post(port, path, data)
            t2 = time.perf_counter()
            rows.append((name, f"{code} {'busy' if out.get('busy') else ''}{out.get('error', '')[:70]}".strip(),
                         _latency(prober, t1, t2)))
        # a second long request while the first runs: busy at once; an edit meanwhile drops the first
        result: dict[str, tuple[int, dict]] = {}
        w = _state(port)["waypoints"]
        k = len(w) // 2
        th = threading.Thread(target=lambda: result.setdefault("plan", _post(port, "/api/plan",
                                                                           {"planner": "iabc", "seed": 2})))
        t1 = time.perf_counter()
        th.start()
        time.sleep(0.05)
        code3, _ = _post(port, "/api/edit", {"op": "move", "index": k, "x": w[k][0] + 5.0, "y": w[k][1]})
        code2, out2 = _post(port, "/api/fly", {})
        th.join()
        t2 = time.perf_counter()
        rows.append(("an edit, then a flight, while a re-plan runs", f"edit {code3}, fly {code2}"
                     f"{' busy' if out2.get('busy') else ''}, re-plan {result['plan'][0]}"
                     f"{' superseded' if result['plan'][1].get('superseded') else ''}",
                     _latency(prober, t1, t2)))
        for declared in (True, False):
            with Peak(server.pid) as pk:
                t1 = time.perf_counter()
                code, secs = _big_body(port, 300, declared)
                t2 = time.perf_counter()
            rows.append((f"300 MB body ({'Content-Length' if declared else 'chunked'})",
                         f"{code}; RSS {idle:.0f} → peak {pk.peak:.0f} MB", _latency(prober, t1, t2)))
        with Peak(server.pid) as pk:
            t1 = time.perf_counter()
            ok, answered = _concurrent_checks(port, 600)
            t2 = time.perf_counter()
        rows.append(("600 concurrent POST /api/check", f"{ok} × 200 of {answered} answered; RSS {idle:.0f} → peak "
                     f"{pk.peak:.0f} MB", _latency(prober, t1, t2)))
        prober.stop()
    finally:
        server.terminate()
        server.wait(30)
    log.seek(0)
    tracebacks = log.read().count("Traceback")
    load = os.getloadavg()
    lines = ["| hostile request | answer | worst GET /api/state while it ran |", "|---|---|---|"]
    lines += [f"| {a} | {b} | {c} |" for a, b, c in rows]
    note = (f"`python benchmarks/serve_hostile.py --figure`: `auvplan serve showcase` in its own process; "
            f"tracebacks in the server's log: {tracebacks}; load average {load[0]:.1f}–{load[2]:.1f} on "
            f"{os.cpu_count()} cores.")
    text = "\n".join(lines) + "\n\n" + note
    print(text)
    if args.figure:
        (ROOT / "docs" / "figures" / "serve-hostile.md").write_text(text + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
