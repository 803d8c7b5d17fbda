"""Small synthetic scenes shared by the tests."""

from __future__ import annotations

import numpy as np

from auvplan.world import Bounds, Margins, Terrain, World

# the limits tests' scene (test_vehicle_limits, test_limits_by_hand, test_mission_legs): a ridge 40 m high and 60 m
# wide across a 2 km x 400 m box at x = 1000 m, over a 100 m deep seabed on 5 m cells; the mission crosses it at -80 m
RIDGE_ROUTE = "route = [[100.0, 200.0, -80.0], [1900.0, 200.0, -80.0]]"
RIDGE = """
name = "ridge"
seed = 1
[bounds]
x = [0.0, 2000.0]
y = [0.0, 400.0]
z = [-120.0, 0.0]
[terrain.synthetic]
kind = "ridge"
depth = 100.0
cell_m = 5.0
ridge_x = 1000.0
ridge_width = 60.0
height = 40.0
[mission]
start = [100.0, 200.0, -80.0]
goal = [1900.0, 200.0, -80.0]
min_altitude_m = 10.0
"""


def ridge_toml(*, route: bool = False, follow_altitude_m: float | None = None) -> str:
    """:data:`RIDGE` with, if asked, the straight route written out (:data:`RIDGE_ROUTE`) and a terrain-following
    altitude (``follow_altitude_m = ...``), as the last lines of ``[mission]``."""
    text = RIDGE + (RIDGE_ROUTE + "\n" if route else "")
    return text + (f"follow_altitude_m = {follow_altitude_m}\n" if follow_altitude_m is not None else "")


def build_toml(text: str, source: str = "t.toml") -> tuple:  # type: ignore[type-arg]
    """(World, Mission) of a scenario document given as TOML text."""
    from auvplan.io.scenario import loader as scenario_io

    return scenario_io.build(scenario_io.loads(text, source))


def flat_world(depth: float = 100.0, size: float = 1000.0, min_altitude: float = 5.0, obstacles=(), **kw) -> World:
    """Open square world over a flat seabed."""
    x = np.linspace(0.0, size, 21)
    t = Terrain(x, x, np.full((21, 21), -depth), name="flat")
    return World(Bounds(0.0, size, 0.0, size, -depth, 0.0), t, obstacles=obstacles,
                 margins=Margins(min_altitude=min_altitude, **kw), name="flat")


def stderr_gaps(argv: list[str], timeout: float = 3600.0) -> tuple[int, list[tuple[float, str]]]:
    """Run ``argv`` and time its stderr (issue 56): ``(exit code, [(seconds since the previous stderr line or
    the start, the line)])``, the last entry the time from the last line to the exit (``"<exit>"``).  Lines
    end at ``\\n`` or at a progress bar's ``\\r``; stdout is discarded."""
    import os
    import subprocess
    import time

    t0 = last = time.monotonic()
    proc = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    assert proc.stderr is not None
    gaps: list[tuple[float, str]] = []
    buf = b""
    while chunk := os.read(proc.stderr.fileno(), 4096):
        buf += chunk
        *done, buf = buf.replace(b"\r", b"\n").split(b"\n")
        for line in done:
            if line.strip():
                now = time.monotonic()
                gaps.append((now - last, line.decode(errors="replace")))
                last = now
        if time.monotonic() - t0 > timeout:
            proc.kill()
    code = proc.wait()
    gaps.append((time.monotonic() - last, "<exit>"))
    return code, gaps
