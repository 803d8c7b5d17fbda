"""Small synthetic scenes shared by the tests."""

from __future__ import annotations

import numpy as np

from auvplan.world import Bounds, Margins, Terrain, World

# the holds tests' scene (test_audit17_holds, test_audit18_holds_current, test_audit19_plan_holds): a 3 km square
# south of the equator with no seabed, the mission along y = 1000 m at 15 m deep
HOLDS = """
name = "holds"
[origin]
lat = -7.0
lon = 70.8
[bounds]
x = [0.0, 3000.0]
y = [0.0, 3000.0]
z = [-100.0, 0.0]
[mission]
start = [500.0, 1000.0, -15.0]
goal = [2500.0, 1000.0, -15.0]
"""

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


# the wide ridge of the mission-file tests (test_mission, test_edges12_surfaces), after its ``name``: a ridge 150 m
# high and 2 km wide across a 10 km x 2 km box at x = 5 km, over a 200 m deep seabed on 100 m cells; the mission
# crosses it 150 m deep
WIDE_RIDGE = """
[origin]
lat = 48.0
lon = -125.0
[bounds]
x = [0.0, 10000.0]
y = [0.0, 2000.0]
z = [-300.0, 0.0]
[terrain.synthetic]
kind = "ridge"
depth = 200.0
cell_m = 100.0
ridge_x = 5000.0
ridge_width = 2000.0
height = 150.0
[mission]
start = [500.0, 1000.0, -150.0]
goal = [9500.0, 1000.0, -150.0]
min_altitude_m = 20.0
min_depth_m = 5.0
max_depth_m = 300.0
"""

# the sloping plane of the survey and hostile-input tests (test_survey_corridor, test_hostile_round4), after its
# ``name``: a 6 km x 5 km box over a seabed 50 m deep at the origin sloping down to the north-east, a 0.1 m/s current
# to the north, the mission a loop from (200, -300) 2 m deep, a small IABC
SLOPING_PLANE = """
seed = 2
[origin]
lat = 48.0
lon = -125.0
[bounds]
x = [-500.0, 5500.0]
y = [-1500.0, 3500.0]
z = [-300.0, 0.0]
[terrain.synthetic]
kind = "plane"
depth = 50.0
slope = [-0.01, -0.02]
cell_m = 25.0
[currents]
uniform = [0.0, 0.1, 0.0]
[mission]
start = [200.0, -300.0, -2.0]
goal = [200.0, -300.0, -2.0]
min_altitude_m = 5.0
min_depth_m = 2.0
max_depth_m = 300.0
[vehicle]
speed = 1.5
[planner]
name = "iabc"
population = 16
iterations = 12
control_points = 3
samples = 50
"""

# the zones' plane (test_audit12_edges, test_edges12_surfaces, test_audit14), after its ``name`` and up to the end of
# ``[mission]``'s start and goal: a 3 km x 1 km box over a flat seabed 200 m deep on 100 m cells, the mission from
# (100, 500) 150 m deep up to (2100, 500) 10 m deep
ZONES_PLANE = """
[origin]
lat = 48.0
lon = -125.0
[bounds]
x = [0.0, 3000.0]
y = [0.0, 1000.0]
z = [-300.0, 0.0]
[terrain.synthetic]
kind = "plane"
depth = 200.0
cell_m = 100.0
[mission]
start = [100.0, 500.0, -150.0]
goal = [2100.0, 500.0, -10.0]
"""


# the flat sea of the mission-file verdict tests (test_qgc_items, test_mission_verdicts), after its ``name``: a 16 km x
# 12 km box off Guam (16 N, 145 E) over a flat seabed 300 m deep on 500 m cells, the mission across it at the surface
FLAT_SEA = """seed = 1
[origin]
lat = 16.0
lon = 145.0
[bounds]
x = [0.0, 16000.0]
y = [0.0, 12000.0]
z = [-600.0, 0.0]
[terrain.synthetic]
kind = "flat"
depth = 300.0
cell_m = 500.0
[mission]
start = [1000.0, 6000.0, 0.0]
goal = [15000.0, 6000.0, 0.0]
min_altitude_m = 20.0
min_depth_m = 0.0
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


def no_seabed() -> np.ndarray:
    """The seabed coefficients ``(1, 1, 4)`` a kernel is given for a world without a seabed (never read): read-only
    like a :class:`Terrain`'s, so that the kernel is not compiled a second time for a writable array."""
    coef = np.zeros((1, 1, 4))
    coef.setflags(write=False)
    return coef


def flat_world(depth: float = 100.0, size: float = 1000.0, min_altitude: float = 5.0, obstacles=(), **kw) -> World:
    """Open square world over a flat seabed."""
    x = np.linspace(0.0, size, 21)
    t = Terrain(x, x, np.full((21, 21), -depth), name="flat")
    return World(Bounds(0.0, size, 0.0, size, -depth, 0.0), t, obstacles=obstacles,
                 margins=Margins(min_altitude=min_altitude, **kw), name="flat")


def stderr_gaps(argv: list[str], timeout: float = 3600.0, env: dict[str, str] | None = None,
                ) -> tuple[int, list[tuple[float, str]]]:
    """Run ``argv`` and time its stderr (issue 56): ``(exit code, [(seconds since the previous stderr line or
    the start, the line)])``, the last entry the time from the last line to the exit (``"<exit>"``).  Lines
    end at ``\\n`` or at a progress bar's ``\\r``; a line is timed when its first characters arrive (a bar
    is drawn as ``\\r`` and its text, the ``\\r`` ending it comes with the next draw); stdout is discarded."""
    import os
    import subprocess
    import time

    t0 = last = time.monotonic()
    proc = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env)
    assert proc.stderr is not None
    gaps: list[tuple[float, str]] = []
    buf, timed = b"", -1  # timed: index in gaps of the unfinished line in buf, once it showed characters
    while chunk := os.read(proc.stderr.fileno(), 4096):
        now = time.monotonic()
        *done, buf = (buf + chunk).replace(b"\r", b"\n").split(b"\n")
        for k, line in enumerate(done):
            if k == 0 and timed >= 0:  # finished now, shown when it began
                gaps[timed] = (gaps[timed][0], line.decode(errors="replace"))
            elif line.strip():
                gaps.append((now - last, line.decode(errors="replace")))
                last = now
        timed = -1 if done else timed
        if buf.strip() and timed < 0:
            gaps.append((now - last, buf.decode(errors="replace")))
            last, timed = now, len(gaps) - 1
        elif timed >= 0:
            gaps[timed] = (gaps[timed][0], buf.decode(errors="replace"))
        if time.monotonic() - t0 > timeout:
            proc.kill()
    code = proc.wait()
    gaps.append((time.monotonic() - last, "<exit>"))
    return code, gaps


def coarse_tides(folder) -> str:
    """``juan-de-fuca-tides`` (real bathymetry and tides) on a 2 km lattice of one level, the energy and point of
    no return integrated every km: a cheap real departure sweep (a TOML file in ``folder``; its path)."""
    from pathlib import Path

    from auvplan.io.scenario.builtins import resolve

    text = Path(resolve("juan-de-fuca-tides")).read_text(encoding="utf-8")
    text = text.replace("cell = 500.0", "cell = 2000.0").replace("levels = 4", "levels = 1")
    assert "cell = 2000.0" in text and "levels = 1" in text
    path = Path(folder) / "jdf-coarse.toml"
    path.write_text(text + "\n[endurance]\nds_m = 1000.0\n", encoding="utf-8")
    return str(path)

