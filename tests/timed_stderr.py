"""A process's stderr timed from inside it, less the time it could not run (tests/integration/test_never_silent.py).

The test's job calls :func:`record` first: every write to ``sys.stderr`` that shows text is timed, and a control
thread wakes every :data:`TICK_S` — a wake that comes late measures a stall of the whole process (not run by a
loaded machine, or its threads not let in), which delays the reporter's thread just as much and which no code can
shorten.  :func:`silent_spans` gives each silence between two lines (and from the last line to the exit) with the
stalls inside it taken out."""

from __future__ import annotations

import atexit
import json
import sys
import threading
import time
from typing import Any

TICK_S = 0.05
"""The control thread's period (s)."""

JITTER_S = 0.02
"""A wake later than this after its period counts as a stall (the interpreter's switch interval, 5 ms, and an
unloaded scheduler's wake-up fall within it)."""


class _Timed:
    """``sys.stderr``, its writes that show text timed (``time.monotonic``)."""

    def __init__(self, stream: Any, writes: list[tuple[float, str]]) -> None:
        self._stream, self._writes = stream, writes

    def write(self, text: str) -> int:
        if text.strip():
            self._writes.append((time.monotonic(), text))
        return int(self._stream.write(text))

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)


def record(path: str) -> None:
    """Time this process's stderr and its stalls; written to ``path`` (JSON) when the process exits."""
    writes: list[tuple[float, str]] = []
    wakes: list[float] = []

    def control() -> None:
        while True:
            wakes.append(time.monotonic())
            time.sleep(TICK_S)

    threading.Thread(target=control, daemon=True).start()
    sys.stderr = _Timed(sys.stderr, writes)

    def dump() -> None:
        end = time.monotonic()
        with open(path, "w", encoding="utf-8") as fh:
            json.dump({"writes": writes, "wakes": [*wakes, end], "end": end}, fh)

    atexit.register(dump)


def silent_spans(rec: dict[str, Any], after: str) -> list[tuple[float, float, str]]:
    """``(silence less the stalls in it, silence, the line that ended it or '<exit>')`` of each silence from the
    first write holding ``after`` on (s)."""
    writes = rec["writes"]
    first = next(i for i, (_, text) in enumerate(writes) if after in text)
    points = [t for t, _ in writes[first:]] + [rec["end"]]
    labels = [text.strip()[:60] for _, text in writes[first + 1:]] + ["<exit>"]
    wakes = rec["wakes"]
    stalls = [(w0 + TICK_S + JITTER_S, w1) for w0, w1 in zip(wakes, wakes[1:]) if w1 - w0 > TICK_S + JITTER_S]
    out = []
    for a, b, label in zip(points, points[1:], labels):
        stolen = sum(max(0.0, min(b, s1) - max(a, s0)) for s0, s1 in stalls)
        out.append((b - a - stolen, b - a, label))
    return out
