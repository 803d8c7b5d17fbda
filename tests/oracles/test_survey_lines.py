"""Depth-adaptive survey lines (issue 37): the analytic slope case of the 2023 CUMCM problem B against a
closed form derived here by hand, and overlap bounds over a seabed with a scarp and a pit checked by an
independent root finder."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from scipy.optimize import brentq

from auvplan.survey import LineParams, Sensor, place_lines
from auvplan.survey.lines.placement import from_sn

NMI = 1852.0


def _cumcm_closed_form(d0: float, alpha: float, beta: float, eta: float, half_width: float) -> list[float]:
    """Line positions across a plane seabed, derived by hand.

    x east, depth D(x) = d0 - x tan(alpha) (deeper to the west).  A beam leaving the surface at x at
    beta from the vertical meets the seabed east (up-slope) at t cot(beta) = D(x) - t tan(alpha), i.e.
    t_e = D(x) sin(beta) cos(alpha) / cos(beta - alpha) = k_e D(x), and west (down-slope) at
    t_w = D(x) sin(beta) cos(alpha) / cos(beta + alpha) = k_w D(x).  The first line's west edge is the
    area's: x1 - k_w D(x1) = -half_width.  Going east the seabed shoals, so the next swath is the narrower
    one and the overlap condition is E_i - (x - k_w D(x)) = eta (k_w + k_e) D(x) with E_i = x_i + k_e D(x_i):
    linear in x.  Lines are added until the east edge reaches +half_width.
    """
    ta = math.tan(alpha)
    k_e = math.sin(beta) * math.cos(alpha) / math.cos(beta - alpha)
    k_w = math.sin(beta) * math.cos(alpha) / math.cos(beta + alpha)
    xs = [(-half_width + k_w * d0) / (1.0 + k_w * ta)]
    while xs[-1] + k_e * (d0 - xs[-1] * ta) < half_width:
        e = xs[-1] + k_e * (d0 - xs[-1] * ta)
        k = k_w + k_e
        xs.append((e + k_w * d0 - eta * k * d0) / (1.0 + k_w * ta - eta * k * ta))
    return xs


def test_cumcm_2023_b_slope_matches_the_closed_form():
    alpha, beta = math.radians(1.5), math.radians(60.0)
    expected = _cumcm_closed_form(110.0, alpha, beta, 0.10, 2 * NMI)

    def seabed(x, y):
        return -(110.0 - np.asarray(x) * math.tan(alpha)) + 0.0 * np.asarray(y)

    area = shapely.box(-2 * NMI, -NMI, 2 * NMI, NMI)  # 4 nmi east-west, 2 nmi north-south
    lines = place_lines(seabed, area, Sensor("multibeam", 120.0), 0.0, LineParams(0.10, 0.20, station_m=400.0))
    got = [ln.c[0] for ln in lines.lines]
    assert lines.complete
    assert len(got) == len(expected) == 34  # the published answer: 34 lines
    np.testing.assert_allclose(got, expected, atol=1e-6)
    np.testing.assert_allclose(np.diff(got), np.diff(expected), atol=1e-6)
    for ln in lines.lines:  # straight lines (a plane has no reason to bend them), each over the whole area
        assert np.ptp(ln.c[ln.active]) < 1e-6
        assert (ln.first, ln.last) == (0, lines.stations.size - 1)
    total = sum(float(np.ptp(lines.stations[ln.active])) for ln in lines.lines)
    assert total == pytest.approx(len(expected) * 2 * NMI) == pytest.approx(125936.0)
    ov = np.concatenate(lines.overlaps())
    np.testing.assert_allclose(ov, 0.10, atol=1e-9)


def _scarp_and_pit(x, y):
    x, y = np.asarray(x, float), np.asarray(y, float)
    depth = 60.0 + 30.0 * (x > 700.0)  # a 30 m scarp along y at x = 700 m
    depth = depth + 25.0 * np.exp(-((x - 1300.0) ** 2 + (y - 1000.0) ** 2) / (2 * 150.0**2))  # a 25 m pit
    return -depth


def _edge(seabed, sensor, x, y, z, direction, t_max=2000.0):
    """Independent swath edge: the first sign change on a 0.05 m grid, refined by Brent's method."""
    if sensor.kind == "multibeam":
        cot = 1.0 / math.tan(math.radians(sensor.opening_deg) / 2)

        def f(t):
            return z - t * cot - seabed(x + direction * t, y)
    else:
        def f(t):
            return sensor.range_m**2 - t * t - (z - seabed(x + direction * t, y)) ** 2
        t_max = sensor.range_m
    t = np.arange(0.0, t_max, 0.05)
    vals = np.broadcast_to(f(t), t.shape)  # the same function on the whole grid at once
    j = int(np.argmax(vals <= 0))
    if vals[j - 1] > 0 and abs(vals[j - 1] - vals[j]) > 10.0:  # the beam meets the scarp's vertical face
        return float(t[j - 1])
    return brentq(lambda v: float(f(v)), t[j - 1], t[j])


@pytest.mark.parametrize("sensor", [Sensor("multibeam", 120.0),
                                    Sensor("multibeam", 120.0, mounting="auv", altitude_m=30.0),
                                    Sensor("sidescan", range_m=120.0, mounting="auv", altitude_m=20.0)],
                         ids=["multibeam-surface", "multibeam-auv", "sidescan-auv"])
def test_overlap_within_bounds_over_a_scarp_and_a_pit(sensor):
    params = LineParams(0.10, 0.20, station_m=25.0, step_m=1.0, pitch_max_deg=15.0)
    area = shapely.box(0.0, 0.0, 2000.0, 2000.0)
    lines = place_lines(_scarp_and_pit, area, sensor, 0.0, params)
    assert lines.complete
    tol = 2 * params.step_m / min(float(np.nanmin(ln.left + ln.right)) for ln in lines.lines)
    ks = np.sort(np.random.default_rng(5).choice(lines.stations.size, 16, replace=False))
    edges = []  # independent swath edges of every line at 16 random stations
    for ln in lines.lines:
        k = ks[(ks >= ln.first) & (ks <= ln.last)]
        x, y = from_sn(lines.stations[k], ln.c[k], 0.0)
        left = np.array([_edge(_scarp_and_pit, sensor, a, b, z, -1.0) for a, b, z in zip(x, y, ln.z[k])])
        right = np.array([_edge(_scarp_and_pit, sensor, a, b, z, 1.0) for a, b, z in zip(x, y, ln.z[k])])
        np.testing.assert_allclose(left, ln.left[k], atol=params.step_m)
        np.testing.assert_allclose(right, ln.right[k], atol=params.step_m)
        if sensor.kind == "sidescan":  # the nadir gap: the blind cone's edge, a fan of nadir_deg
            cone = Sensor("multibeam", sensor.nadir_deg)
            reach = 4 * sensor.altitude_m
            gl = np.array([_edge(_scarp_and_pit, cone, a, b, z, -1.0, reach) for a, b, z in zip(x, y, ln.z[k])])
            gr = np.array([_edge(_scarp_and_pit, cone, a, b, z, 1.0, reach) for a, b, z in zip(x, y, ln.z[k])])
            np.testing.assert_allclose(gr, ln.gap_right[k], atol=params.step_m)
        else:
            gl = gr = np.zeros(k.size)
        edges.append(dict(zip(k.tolist(), zip(x - left, x - gl, x + gr, x + right))))
    checked = 0
    for a, b in zip(edges[:-1], edges[1:]):
        for k in set(a) & set(b):
            (a0, ga0, ga1, a1), (b0, gb0, gb1, b1) = a[k], b[k]
            if b0 < lines.area_hi[k] and a1 > lines.area_lo[k]:
                if sensor.kind == "sidescan":  # each swath reaches past the other's nadir (gap middle)
                    eta = min(a1 - 0.5 * (gb0 + gb1), 0.5 * (ga0 + ga1) - b0) / min(a1 - ga1, gb0 - b0)
                    assert b0 < 0.5 * (ga0 + ga1) and a1 > 0.5 * (gb0 + gb1)  # each half-gap covered by a neighbour
                else:
                    eta = (a1 - b0) / min(a1 - a0, b1 - b0)
                assert 0.10 - tol <= eta <= 0.20 + tol
                checked += 1
    assert checked >= 16
    ov = np.concatenate(lines.overlaps())
    assert ov.min() >= 0.10 - 1e-9 and ov.max() <= 0.20 + tol
    # every station's pair overlap, recomputed from the line arrays by hand
    for a, b, o in zip(lines.lines[:-1], lines.lines[1:], lines.overlaps()):
        k = np.arange(max(a.first, b.first), min(a.last, b.last) + 1)
        ea, eb = a.c[k] + a.right[k], b.c[k] - b.left[k]
        keep = (eb < lines.area_hi[k]) & (ea > lines.area_lo[k])
        if sensor.kind == "sidescan":
            ma, mb = a.c[k] + 0.5 * (a.gap_right[k] - a.gap_left[k]), b.c[k] + 0.5 * (b.gap_right[k] - b.gap_left[k])
            band = np.minimum(ea - (a.c[k] + a.gap_right[k]), (b.c[k] - b.gap_left[k]) - eb)
            mine = (np.minimum(ea - mb, ma - eb) / band)[keep]
        else:
            mine = (ea - eb)[keep] / np.minimum((a.left + a.right)[k], (b.left + b.right)[k])[keep]
        np.testing.assert_allclose(mine, o)
    if sensor.mounting == "auv":  # the altitude held, within the pitch limit
        for ln in lines.lines:
            a = ln.active
            x, y = from_sn(lines.stations[a], ln.c[a], 0.0)
            assert np.all(ln.z[a] - _scarp_and_pit(x, y) >= sensor.altitude_m - 1e-9)
            climb = np.abs(np.diff(ln.z[a])) / np.hypot(np.diff(x), np.diff(y))
            assert np.degrees(np.arctan(climb.max())) <= params.pitch_max_deg + 1e-9


def test_lines_close_up_where_the_seabed_shoals():
    """Over the scarp (deep east of x = 700 m) the surface multibeam's lines are farther apart in deep water."""
    lines = place_lines(_scarp_and_pit, shapely.box(0, 0, 2000, 2000), Sensor(), 0.0, LineParams(station_m=50.0))
    c = np.array([ln.c[0] for ln in lines.lines])  # station 0 (y = 0) is clear of the pit
    gaps = np.diff(c)
    shallow, deep = gaps[c[1:] < 650], gaps[c[:-1] > 760]
    assert shallow.size and deep.size and deep.min() > 1.4 * shallow.max()


def test_auv_climbs_the_scarp_within_the_pitch_limit():
    """Lines across the scarp: the AUV holds at least its altitude and never climbs steeper than the limit."""
    sensor = Sensor("multibeam", 120.0, mounting="auv", altitude_m=30.0)
    params = LineParams(0.10, 0.20, station_m=10.0, step_m=1.0, pitch_max_deg=15.0)
    lines = place_lines(_scarp_and_pit, shapely.box(0.0, 0.0, 1500.0, 600.0), sensor, math.pi / 2, params)
    assert lines.complete
    steepest = 0.0
    for ln in lines.lines:
        a = ln.active
        x, y = from_sn(lines.stations[a], ln.c[a], math.pi / 2)
        assert np.all(ln.z[a] - _scarp_and_pit(x, y) >= sensor.altitude_m - 1e-9)
        climb = np.degrees(np.arctan(np.abs(np.diff(ln.z[a])) / np.hypot(np.diff(x), np.diff(y))))
        steepest = max(steepest, float(climb.max()))
    assert 14.9 <= steepest <= params.pitch_max_deg + 1e-9  # the limit binds at the 30 m scarp
    assert np.concatenate(lines.overlaps()).min() >= 0.10 - 1e-9


def test_coverage_gaps_and_overlap_of_known_footprints():
    """Two straight lines over a flat 50 m seabed: swaths of half-width 50 tan 60° each, one gap between them."""
    from auvplan.survey import SurveyLine, SurveyLines
    from auvplan.survey.coverage import footprints, measure

    def flat(x, y):
        return np.full(np.shape(x), -50.0)

    half = 50.0 * math.tan(math.radians(60.0))
    y = np.linspace(0.0, 400.0, 9)
    pts = np.vstack([np.column_stack([np.full(9, 80.0), y, np.zeros(9)]),
                     np.column_stack([np.full(9, 300.0), y[::-1], np.zeros(9)])])
    labels = np.repeat([0, 1], 9)
    right = np.tile([1.0, 0.0], (18, 1))  # heading north: the fan's right side is east
    fps = footprints(flat, Sensor(), pts, right, labels, 2, 1.0)
    dummy = SurveyLine(np.zeros(9), np.zeros(9), np.zeros(9), np.zeros(9), 0, 8)
    lines = SurveyLines(0.0, y, np.zeros(9), np.full(9, 1000.0), (dummy, dummy), True)
    cov = measure(shapely.box(0.0, 0.0, 1000.0, 400.0), lines, fps)
    covered = (80.0 + half) + 2 * half  # the first swath is cut at x = 0
    assert cov.coverage_pct == pytest.approx(100.0 * covered / 1000.0, abs=1e-9)
    assert len(cov.gaps) == 2 and cov.gap_area_m2 == pytest.approx(400.0 * (1000.0 - covered), rel=1e-9)
    np.testing.assert_allclose(cov.overlap[0], ((80.0 + half) - (300.0 - half)) / (2 * half), atol=1e-9)


def test_the_chosen_heading_runs_the_lines_along_a_long_flat_area():
    """Over a flat seabed the shortest survey of a long strip has few, long lines: along its long side."""
    from auvplan.survey.mission import SurveyParams, choose_heading

    def flat(x, y):
        return np.full(np.shape(x), -40.0)

    for box, along in ((shapely.box(0, 0, 3000, 600), math.pi / 2), (shapely.box(0, 0, 600, 3000), 0.0)):
        heading = choose_heading(flat, SurveyParams(box, Sensor(), LineParams(station_m=100.0)))
        assert abs(math.sin(heading - along)) < 1e-9
