"""Audit 21: corridor surveys at the centre line's bends, gliders.

Oracles written here from scratch: the corridor as every point within half the width of the centre line
*as given* (numpy point-to-segment distances, flat at the two ends), and the swath footprint on a flat
seabed, every point within ``(D - draft) tan(opening / 2)`` of a planned line (the fan across a parallel
of the centre line covers exactly the points that close to it inside the frame's one-to-one band).
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

from auvplan.survey.lines.corridor import build_corridor, default_bend_radius
from auvplan.survey.lines.placement import LineParams, place_lines
from auvplan.survey.lines.swath import Sensor

DEPTH, DRAFT, OPENING = 50.0, 2.0, 120.0


def _seg_dist(q, a, b):
    """Distances of points ``q`` (K, 2) to the segment ``a b``, and the projection's fraction along it."""
    d = b - a
    t = ((q - a) @ d) / (d @ d)
    foot = a + np.clip(t, 0.0, 1.0)[:, None] * d
    return np.hypot(*(q - foot).T), t


def _in_given_corridor(q, pts, widths):
    """Points within half the width of the polyline (width interpolated along each leg), flat-capped."""
    inside = np.zeros(len(q), dtype=bool)
    last = len(pts) - 2
    for i in range(last + 1):
        dist, t = _seg_dist(q, pts[i], pts[i + 1])
        half = 0.5 * (widths[i] + np.clip(t, 0.0, 1.0) * (widths[i + 1] - widths[i]))
        ok = dist <= half
        if i == 0:
            ok &= t >= 0.0
        if i == last:
            ok &= t <= 1.0
        inside |= ok
    return inside


def _bent(angle_deg, turn):
    a = math.radians(angle_deg)
    return np.array([[0.0, 0.0], [2000.0, 0.0], [2000.0 + 1500.0 * math.cos(a), turn * 1500.0 * math.sin(a)]])


def _samples(pts, pad, step=5.0):
    x0, y0 = pts.min(axis=0) - pad
    x1, y1 = pts.max(axis=0) + pad
    gx, gy = np.meshgrid(np.arange(x0, x1, step), np.arange(y0, y1, step))
    return np.column_stack([gx.ravel(), gy.ravel()])


CASES = [  # (bend angle, turn: +1 left / -1 right, widths per vertex)
    (75.0, 1.0, (300.0, 300.0, 300.0)),
    (75.0, -1.0, (300.0, 300.0, 300.0)),
    (60.0, -1.0, (260.0, 320.0, 200.0)),
]


@pytest.mark.parametrize(("angle", "turn", "widths"), CASES)
def test_the_corridor_surveyed_holds_the_corridor_about_the_given_centre_line(angle, turn, widths):
    """The band about the *rounded* centre line left out the outside of every bend: 14 200 m² (75°, left) and
    22 400 m² (75°, right) of a 300 m corridor, 80 m deep at the corner, never surveyed nor reported."""
    pts = _bent(angle, turn)
    w = np.asarray(widths) if len(set(widths)) > 1 else np.asarray(widths[:1])
    c = build_corridor(pts, w, default_bend_radius(w, 10.0))
    q = _samples(pts, 400.0)
    given = _in_given_corridor(q, pts, np.asarray(widths))
    import shapely

    inside = shapely.contains_xy(shapely.buffer(c.area, 0.5), q[:, 0], q[:, 1])
    assert given.sum() > 10_000
    assert np.all(inside[given]), f"{int((given & ~inside).sum())} samples of the corridor left out"


@functools.lru_cache(maxsize=2)
def _bent_lines(angle, turn, width):
    """The lines over a flat seabed of the corridor about the bent centre line (shared by the tests below)."""
    pts = _bent(angle, turn)
    w = np.array([width])
    c = build_corridor(pts, w, default_bend_radius(w, 10.0))
    sensor = Sensor(opening_deg=OPENING)
    return pts, place_lines(lambda x, y: np.full(np.shape(x), -DEPTH), c.area, sensor, c.frame.heading,
                            LineParams(surface_z=-DRAFT), c.frame)


@pytest.mark.parametrize(("angle", "turn", "widths"), CASES[:2])
def test_the_planned_swaths_cover_the_given_corridor_at_a_sharp_bend(angle, turn, widths):
    """Before: 98.65 % (left turn) and 97.86 % (right turn) of the corridor covered, the survey reporting 100 %."""
    pts, lines = _bent_lines(angle, turn, widths[0])
    assert lines.complete
    reach = (DEPTH - DRAFT) * math.tan(math.radians(OPENING / 2))
    q = _samples(pts, 400.0, 8.0)
    q = q[_in_given_corridor(q, pts, np.asarray(widths))]
    best = np.full(len(q), np.inf)
    for i in range(len(lines.lines)):
        wp = lines.waypoints(i)[:, :2]
        for a, b in zip(wp[:-1], wp[1:], strict=True):
            best = np.minimum(best, _seg_dist(q, a, b)[0])
    covered = 100.0 * np.mean(best <= reach + 0.5)
    assert covered >= 99.9, f"{covered:.2f} % of the corridor under the swaths"


@pytest.mark.parametrize("turn", [1.0, -1.0])
def test_tie_lines_spread_along_a_corridor_with_a_line_only_at_its_bend(turn):
    """A line added only over the bend's outer wedge (stations 34-45 of 70) drew the ties there: two ties, at
    stations 34 and 45 (36 and 43 for the left turn), instead of three spread along.  Oracle: the even shares
    of the stations (11.5, 34.5, 57.5 of 70) within a station, and each tie meeting (within 1 m: the wedge's
    line may start on the tie's cut) every main line flown at its station."""
    import shapely

    from auvplan.survey.ties import tie_lines, tie_stations

    _, lines = _bent_lines(75.0, turn, 300.0)
    k = lines.stations.size
    partial = [ln for ln in lines.lines if ln.last - ln.first < 0.5 * (k - 1)]
    assert partial  # the bend's line
    idx = tie_stations(lines, 3)
    np.testing.assert_allclose(idx, (np.arange(3) + 0.5) / 3 * (k - 1), atol=1.0)
    for i, tie in zip(idx, tie_lines(lines, 3, 60.0, False, 20.0), strict=True):
        on = [j for j, ln in enumerate(lines.lines) if ln.first <= i <= ln.last]
        assert all(shapely.distance(shapely.LineString(tie[:, :2]), shapely.LineString(lines.waypoints(j)[:, :2]))
                   < 1.0 for j in on)


def test_a_corner_too_sharp_for_the_frame_is_refused_with_its_message():
    """A 130° corner: the given corridor's outer edge beyond the rounded frame's one-to-one band."""
    pts = _bent(130.0, 1.0)
    w = np.array([300.0])
    with pytest.raises(ValueError, match="too sharp"):
        build_corridor(pts, w, default_bend_radius(w, 10.0))


# --- gliders ---------------------------------------------------------------------------------------------


class _Wall:
    """A flat 1000 m seabed with a wall rising at ``grade`` from ``x0`` to a 100 m plateau; no current."""

    def __init__(self, x0: float, grade: float) -> None:
        self.x0, self.grade = x0, grade
        self.currents = self

    def seabed(self, x, y):
        return np.clip(-1000.0 + self.grade * (np.asarray(x, dtype=float) - self.x0), -1000.0, -100.0)

    def velocity(self, p, t):
        return np.zeros((len(p), 3))


@pytest.mark.parametrize(("x0", "grade"), [(1700.0, 1.0), (1500.0, 1.0), (1650.0, 0.7)])
def test_a_glider_never_flies_under_the_seabed_it_climbs_towards(x0, grade):
    """The altimeter turned dives only and a climb was never checked against the seabed: a Slocum climbing at
    ~26° into a 45° wall flew on 33 m inside the rock (x0 = 1700) and reported ``arrived``.  Oracle: the
    seabed under every track sample (and every tenth of every step); a flight that meets it ends grounded."""
    from auvplan.sim.glider import fly_glider
    from auvplan.vehicles.glider import GliderParams

    world = _Wall(x0, grade)
    g = GliderParams(dive_depth_m=200.0, yos=3, capture_radius_m=500.0)
    tr = fly_glider(world, g, (0.0, 0.0), [(4000.0, 0.0)], 0.0, min_altitude=10.0, max_s=6 * 3600.0)
    p = np.linspace(tr.xyz[:-1], tr.xyz[1:], 11, axis=1).reshape(-1, 3)
    clearance = p[:, 2] - world.seabed(p[:, 0], p[:, 1])
    if tr.reason == "arrived":
        assert clearance.min() >= 0.0, f"{-clearance.min():.1f} m under the seabed, reported arrived"
    else:
        assert tr.reason == "grounded" and clearance.min() >= -2.0  # stopped within a step of the contact


@pytest.mark.parametrize(("mission_max", "rating"), [("max_depth_m = 100.0", ""), ("", "max_depth_m = 150.0")])
def test_a_dive_deeper_than_the_depth_band_is_refused_naming_the_key(mission_max, rating):
    """``dive_depth_m = 200`` with ``[mission] max_depth_m = 100`` (or a 150 m rating) was accepted and the
    glider dived to 200 m (and yo10.ma sent it there)."""
    from auvplan.errors import ScenarioError
    from auvplan.io.scenario import loader as scenario_io

    text = f"""
name = "deep-glider"
[bounds]
x = [-1000.0, 30000.0]
y = [-5000.0, 5000.0]
z = [-500.0, 0.0]
[terrain.synthetic]
kind = "plane"
depth = 400.0
slope = [0.0, 0.0]
cell_m = 500.0
[mission]
start = [0.0, 0.0, -10.0]
goal = [20000.0, 0.0, -10.0]
{mission_max}
[vehicle]
type = "glider"
{rating}
[vehicle.glider]
dive_depth_m = 200.0
"""
    with pytest.raises(ScenarioError, match=r"deep-glider.toml: \[vehicle.glider\] dive_depth_m = 200"):
        scenario_io.build(scenario_io.loads(text, "deep-glider.toml"))


GLIDER_CHECK = """
name = "yo-check"
[origin]
lat = 60.0
lon = 5.0
[bounds]
x = [-2000.0, 8000.0]
y = [-3000.0, 3000.0]
z = [-500.0, 0.0]
[terrain.synthetic]
kind = "plane"
depth = 400.0
slope = [0.0, 0.0]
cell_m = 500.0
[mission]
start = [0.0, 0.0, -10.0]
goal = [4000.0, 0.0, -10.0]
min_altitude_m = 10.0
max_depth_m = 300.0
[vehicle]
type = "glider"
[vehicle.glider]
dive_depth_m = 200.0
capture_radius_m = 500.0
[planner]
name = "timeopt"
"""


@pytest.mark.parametrize(("edit", "needle"), [
    (("d_target_depth(m) 200", "d_target_depth(m) 900"), "yo10.ma: d_target_depth 900 m is deeper than the depth "
                                                         "band's 300 m"),
    (("c_target_depth(m) 10", "c_target_depth(m) 250"), "yo10.ma: climb_depth_m = 250"),
    (None, ""),
])
def test_mission_check_reads_the_yo_file_s_depths_as_the_glider_does(tmp_path, edit, needle):
    """``mission check`` read yo10.ma for its altitude only: a file sending the glider to 900 m through a 300 m
    band, or climbing to 250 m only to dive to 200, was flown with the scenario's yos and passed."""
    from auvplan.app.glider import check_glider_files
    from auvplan.io.missions.glider import slocum_files
    from auvplan.vehicles.glider import GliderParams

    scen = tmp_path / "yo-check.toml"
    scen.write_text(GLIDER_CHECK)
    files = slocum_files(np.array([[2000.0, 0.0], [4000.0, 0.0]]), (60.0, 5.0),
                         GliderParams(dive_depth_m=200.0, capture_radius_m=500.0), 10.0)
    if edit:
        assert edit[0] in files["yo10.ma"]
        files["yo10.ma"] = files["yo10.ma"].replace(*edit)
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    (rec,) = check_glider_files(str(scen), [str(tmp_path / "goto_l10.ma")])
    assert rec["ok"] is (not needle), rec["message"]
    assert needle in rec["message"]
