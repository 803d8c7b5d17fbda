"""Audit 24 of the survey code: bugs the fixtures never reached because they never varied what the bug depends on
(a thin strip of an area, ...). Each test has an independent oracle worked out by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from auvplan.survey.coverage import lawnmower
from auvplan.survey.lines.swath import Sensor


def _flat(depth: float):  # noqa: ANN202
    return lambda x, y: np.full(np.broadcast(np.asarray(x), np.asarray(y)).shape, -depth)


@pytest.mark.parametrize(("width", "heading_deg"), [(12.0, 90.0), (30.0, 90.0), (39.0, 90.0), (30.0, 0.0)])
def test_the_lawnmower_of_a_strip_narrower_than_its_sampling_grid(width, heading_deg):
    """A 4 km x ``width`` strip over a flat 50 m seabed: its shallowest depth is 50 m.  The lawnmower sampled the
    seabed on a grid of a hundredth of the area's longer side (40 m) and read no sample inside a strip narrower than
    that: ``np.max`` of nothing, a ValueError out of ``auvplan survey`` (exit 2, 'zero-size array') on a valid strip.
    By hand: a 120° fan over 50 m reaches 50 tan 60° either side, the lanes 0.9 x 2 x 86.6 = 155.9 m apart; along
    the strip (90°) one lane of 4 km + 2 x 60 m run-in; across it (0°) a lane every 155.9 m or less over the 4 km
    less the swath, each the strip's width + 2 x 60 m long."""
    area = shapely.box(0.0, 0.0, 4000.0, width)
    mower = lawnmower(_flat(50.0), area, Sensor(), math.radians(heading_deg), 0.1, 0.0, 60.0)
    reach = 50.0 * math.tan(math.radians(60.0))
    assert mower.shallowest_m == pytest.approx(50.0)
    assert mower.spacing_m == pytest.approx(0.9 * 2.0 * reach)
    if heading_deg == 90.0:
        assert mower.lines == 1 and mower.line_length_m == pytest.approx(4000.0 + 120.0, abs=2.5)
    else:
        count = math.ceil((4000.0 - 2.0 * reach) / (0.9 * 2.0 * reach)) + 1
        assert mower.lines == count and mower.line_length_m == pytest.approx(count * (width + 120.0), rel=1e-6)


@pytest.mark.parametrize("pts", [
    [[0.0, 0.0], [2000.0, 0.0], [3300.0, 1500.0], [4800.0, 1500.0], [4860.0, 1500.0]],  # a 60 m last leg
    [[0.0, 0.0], [40.0, 0.0], [2000.0, 0.0], [3300.0, 1500.0], [4800.0, 1500.0]],  # a 40 m first leg
    [[0.0, 0.0], [0.0, 0.0], [2000.0, 0.0], [3300.0, 1500.0]],  # the first vertex given twice
    [[0.0, 0.0], [2000.0, 0.0], [2000.0, 0.0], [3300.0, 1500.0]],  # an inner vertex given twice
])
def test_widths_per_vertex_all_equal_give_the_corridor_of_one_width(pts):
    """``widths_m = [600, 600, ...]`` is the corridor of ``width_m = 600``: shapely's flat-capped buffer of the
    centre line with round joins (and the band about the rounded line, the same in both).  Each inner vertex of the
    per-vertex band had a whole disc of its half width, which pokes out past the flat end of a leg shorter than half
    the width (300 m past a 60 m last leg less 60 m: the corridor 105 515 m² larger, and `survey` reported 97.9 %
    planned coverage with a 71 333 m² 'gap' beyond the corridor's end, where the lines never go)."""
    from auvplan.survey.lines.corridor import build_corridor

    p = np.asarray(pts)
    one = build_corridor(p, np.array([600.0]), 610.0).area
    per = build_corridor(p, np.full(p.shape[0], 600.0), 610.0).area
    assert shapely.symmetric_difference(one, per).area < 1e-3 * one.area
    # nothing behind the start's flat end nor past the end's
    d0 = (p[2] - p[0]) / np.linalg.norm(p[2] - p[0]) if np.allclose(p[0], p[1]) else (p[1] - p[0]) / np.linalg.norm(
        p[1] - p[0])
    d1 = (p[-1] - p[-2]) / np.linalg.norm(p[-1] - p[-2])
    ring = shapely.get_coordinates(shapely.segmentize(per.exterior, 5.0))
    assert ((ring - p[0]) @ d0).min() > -1.0 and ((ring - p[-1]) @ d1).max() < 1.0


def test_widths_per_vertex_stay_within_the_flat_ends_and_cover_every_leg():
    """Widths 300 -> 800 -> 500 m along a line with a 50 m first leg and a 45° bend: the band holds every point of
    each leg's own trapezoid (the widths interpolated along it, checked at 2 000 points), and nothing past the flat
    ends (the old disc of 400 m at the second vertex reached 350 m behind the start)."""
    from auvplan.survey.lines.corridor import given_band

    p = np.array([[0.0, 0.0], [50.0, 0.0], [3000.0, 0.0], [5000.0, 2000.0]])
    w = np.array([300.0, 800.0, 800.0, 500.0])
    band = given_band(p, w)
    rng = np.random.default_rng(24)
    for i in range(3):
        d = p[i + 1] - p[i]
        t, u = rng.uniform(0.0, 1.0, 2000), rng.uniform(-0.499, 0.499, 2000)
        half_w = (1 - t) * w[i] + t * w[i + 1]
        q = p[i] + t[:, None] * d + (u * half_w)[:, None] * np.array([d[1], -d[0]]) / np.linalg.norm(d)
        assert shapely.contains_xy(band, q[:, 0], q[:, 1]).all()
    ring = shapely.get_coordinates(shapely.segmentize(band.exterior, 5.0))
    assert (ring[:, 0] > -1.0).all()
    d1 = (p[-1] - p[-2]) / np.linalg.norm(p[-1] - p[-2])
    assert ((ring - p[-1]) @ d1).max() < 1.0


def _lines_measured(seabed, area, sensor, heading, lp):  # noqa: ANN001, ANN202
    """The lines placed, and their overlaps measured on the footprints of the lines flown without run-ins."""
    from auvplan.survey.coverage import footprints, measure
    from auvplan.survey.lines.placement import place_lines

    lines = place_lines(seabed, area, sensor, heading, lp)
    pts = [lines.waypoints(k) for k in range(len(lines.lines))]
    lab = np.concatenate([np.full(len(p), k) for k, p in enumerate(pts)])
    route = np.vstack(pts)
    right = lines.geom.right(lines.geom.to_sn(route[:, 0], route[:, 1])[0])
    fps = footprints(seabed, sensor, route, right, lab, len(pts), lp.step_m)
    return lines, measure(area, lines, fps)


@pytest.mark.parametrize("heading_deg", [37.0, 0.0])
def test_overlap_measured_at_the_lines_ends_without_run_ins(heading_deg):
    """``run_in_m = 0``: a line's footprint ends on the cut across the track at its first and last station, where
    shapely's cut of the footprint returned a part of it: `survey` reported a least overlap of 13.1 % and a greatest
    of 192.7 % for lines placed at 50 % and 10.3 % (an overlap above 100 % is impossible).  The oracle: the planner's
    own overlaps (the reaches of the swath cast in the line frame, no shapely), pair by pair within half a point."""
    from auvplan.survey.lines.placement import LineParams

    def seabed(x, y):  # noqa: ANN001, ANN202
        return -(60.0 + 0.03 * np.asarray(x)) + 0.0 * np.asarray(y)

    area = shapely.box(0.0, 0.0, 1500.0, 1000.0)
    lines, cov = _lines_measured(seabed, area, Sensor("multibeam", 120.0), math.radians(heading_deg),
                                 LineParams(0.5, 0.6, station_m=25.0, step_m=1.0))
    planned = lines.overlaps()
    assert len(planned) == len(cov.overlap) >= 8
    for want, got in zip(planned, cov.overlap, strict=True):
        assert got.size >= want.size - 2
        assert got.min() == pytest.approx(want.min(), abs=0.005) and got.max() == pytest.approx(want.max(), abs=0.005)
    assert cov.coverage_pct >= 99.99  # (without run-ins a corner of a few m² at a slanted edge is left)


def test_one_swath_wider_than_a_strip_is_centred_on_it():
    """A 4 km x 60 m strip over a flat seabed 100 m deep, lines along it: one 120° swath reaches 173 m either side,
    so one line covers it, and it belongs on the strip's middle (y = 30 m).  The first line was placed 'as far in as
    it can be with its swath still reaching the area's edge': 173 m north of the strip's south edge, 113 m outside
    the area the operator drew (over whatever lies there)."""
    from auvplan.survey.lines.placement import LineParams

    area = shapely.box(0.0, 0.0, 4000.0, 60.0)
    lines, cov = _lines_measured(_flat(100.0), area, Sensor("multibeam", 120.0), math.radians(90.0),
                                 LineParams(0.1, 0.2, station_m=50.0, step_m=2.0))
    assert len(lines.lines) == 1 and lines.complete
    np.testing.assert_allclose(lines.waypoints(0)[:, 1], 30.0, atol=1e-3)
    assert cov.coverage_pct == pytest.approx(100.0, abs=1e-6)


def test_a_corridor_narrower_than_the_swath_is_surveyed_along_its_centre_line():
    """A 50 m pipeline corridor bending by 49° and 41° in 100 m of water (a 346 m swath): one line, which belongs on
    the centre line (within 5 m: a bend's outer wedge moves the corridor's middle out).  It was placed 120-148 m off it
    (`survey`: 59-204 m with the run-ins), beyond the 59 m where the corridor's frame is one to one, so it looped at
    the bends (a 155° turn between two stations 25 m apart, a least turn radius of 5 m for a 10 m vehicle, status
    EXACT) and left a 584 m² gap.  Oracles: shapely's distance to the
    rounded centre line, ``is_simple``, and the coverage of the corridor by the swath's footprint."""
    from auvplan.survey.coverage import footprints, measure
    from auvplan.survey.lines.corridor import build_corridor
    from auvplan.survey.lines.placement import LineParams, place_lines

    pts = np.array([[0.0, 0.0], [2000.0, 0.0], [3300.0, 1500.0], [4800.0, 1500.0]])
    corridor = build_corridor(pts, np.array([50.0]), 60.0)
    sensor, lp = Sensor("multibeam", 120.0), LineParams(0.1, 0.2, station_m=25.0, step_m=2.0)
    lines = place_lines(_flat(100.0), corridor.area, sensor, corridor.frame.heading, lp, corridor.frame)
    assert len(lines.lines) == 1 and lines.complete
    w = lines.waypoints(0)
    # on the centre line, but at a bend the corridor holds the given line's outer wedge too, so its middle moves out
    assert shapely.distance(shapely.points(w[:, :2]), corridor.frame.line).max() < 5.0
    assert shapely.contains_xy(corridor.area, w[1:-1, 0], w[1:-1, 1]).all()
    assert shapely.LineString(w[:, :2]).is_simple
    right = corridor.frame.right(corridor.frame.to_sn(w[:, 0], w[:, 1])[0])
    fps = footprints(_flat(100.0), sensor, w, right, np.zeros(len(w), dtype=np.int64), 1, lp.step_m)
    assert measure(corridor.area, lines, fps).coverage_pct >= 99.99


def _radii(p):  # noqa: ANN001, ANN202
    """Radii of the circles through consecutive waypoints (inf on a straight)."""
    a, b, c = p[:-2, :2], p[1:-1, :2], p[2:, :2]
    cross = np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    prod = np.linalg.norm(b - a, axis=1) * np.linalg.norm(c - b, axis=1) * np.linalg.norm(a - c, axis=1)
    return np.where(cross > 1e-12, prod / np.maximum(2.0 * cross, 1e-300), np.inf)


@pytest.mark.parametrize(("width", "bend", "sensor"), [
    (50.0, 60.0, Sensor("sidescan", range_m=150.0, mounting="auv", altitude_m=15.0)),
    (400.0, 250.0, Sensor("multibeam", 120.0)),  # bend_radius_m given, under the default 410 m
])
def test_corridor_lines_stay_where_the_frame_is_one_to_one(width, bend, sensor):
    """Each next line goes as far out as the overlap allows; past the corridor's far edge that put the last line
    beyond ``n_limit`` (0.98 of the bend radius), where a parallel of the rounded centre line folds over itself at a
    bend: a side-scan's second line 108 m off a 50 m corridor's centre line (limit 59 m), a multibeam's last line
    285 m off a 400 m corridor rounded to 250 m (limit 245 m).  The last line now goes no further out than it must to
    finish the corridor where the greedy offset is past the limit.  Oracles: ``is_simple``, the radius of the circles
    through consecutive waypoints (>= the 10 m vehicle's), the coverage of the footprints (side-scan gaps included)."""
    from auvplan.survey.coverage import footprints, measure
    from auvplan.survey.lines.corridor import build_corridor
    from auvplan.survey.lines.placement import LineParams, place_lines

    pts = np.array([[0.0, 0.0], [2000.0, 0.0], [3300.0, 1500.0], [4800.0, 1500.0]])
    corridor = build_corridor(pts, np.array([width]), bend)
    lp = LineParams(0.1, 0.2, station_m=25.0, step_m=2.0)
    lines = place_lines(_flat(100.0), corridor.area, sensor, corridor.frame.heading, lp, corridor.frame)
    assert lines.complete
    pts_all, lab = [], []
    for k in range(len(lines.lines)):
        w = lines.waypoints(k)
        assert shapely.LineString(w[:, :2]).is_simple
        assert _radii(w).min() >= 10.0
        pts_all.append(w)
        lab.append(np.full(len(w), k))
    route = np.vstack(pts_all)
    right = corridor.frame.right(corridor.frame.to_sn(route[:, 0], route[:, 1])[0])
    fps = footprints(_flat(100.0), sensor, route, right, np.concatenate(lab), len(pts_all), lp.step_m)
    assert measure(corridor.area, lines, fps).coverage_pct >= 99.9


def test_the_free_heading_of_a_strip_runs_along_it():
    """A 2 km x 12 m strip over a flat 50 m seabed, no ``heading_deg``: the shortest survey is one line along it
    (2 000 m + 2 x 60 m run-in = 2 120 m).  Across it, 12 lines of 12 m are joined by U-turns of ``πR + D - 2R``
    (Dubins, lines ``D`` = 156 m apart): 12 x 132 + 11 x 167 = 3 421 m.  The estimate counted each turn as ``πR``
    (31 m), leaving out the way across to the next line, and chose the lines across (`survey` flew 2 569 m of survey
    instead of 1 722 m on a 1.6 km strip)."""
    from auvplan.survey.lines.placement import LineParams
    from auvplan.survey.mission import SurveyParams, choose_heading

    params = SurveyParams(shapely.box(0.0, 0.0, 2000.0, 12.0), Sensor("multibeam", 120.0),
                          LineParams(0.1, 0.2, station_m=10.0, step_m=1.0), None, 10.0, 60.0)
    heading = choose_heading(_flat(50.0), params)
    assert abs(math.sin(heading)) == pytest.approx(1.0, abs=1e-9)  # east or west: along the strip
