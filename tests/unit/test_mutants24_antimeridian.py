"""Round 10's survivors of ``io/missions/antimeridian.py`` (docs/mutants.md section 10): the cut at ±180° and its
read-back on what the suite's fixtures never varied — longitudes anywhere (a step of 180.5° whose short way is
across), a line crossing westward from the west side, lines without an altitude column, pieces that meet but are not
a cut (a shared end off the antimeridian, ends on it at other latitudes or depths, empty pieces), and rings that are
closed, carry an altitude, do not meet, or cross at the equator.

Oracles, independent of the module: the short way round of each step by hand (``((d + 180) mod 360) - 180``), the
crossings counted as the number of whole turns the unwrapped longitude passes ±180° by; shapely's area and
Hausdorff distance of the unwrapped geometry; the pieces as a reader would join them end to end.
"""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from auvplan.io.missions.antimeridian import crosses, cut_line, cut_ring, join_line, join_rings


def _unwrap(lon: np.ndarray) -> np.ndarray:
    """Each step the short way round, by hand."""
    return lon[0] + np.r_[0.0, np.cumsum((np.diff(lon) + 180.0) % 360.0 - 180.0)]


def _crossings(lon: np.ndarray) -> int:
    u = _unwrap(lon)
    turn = np.floor((u + 180.0) / 360.0)
    return int(np.abs(np.diff(turn)).sum())


@pytest.mark.parametrize("cols", [2, 3])
def test_lines_anywhere_are_cut_once_per_crossing_and_joined_back(cols):
    """Lines starting anywhere, steps up to 179.5° the short way (a raw step of up to 359.5°): as many pieces as
    crossings plus one, none stepping over 180°, together the unwrapped line, joined the line itself (with and
    without an altitude column)."""
    rng = np.random.default_rng(24 + cols)
    for _ in range(150):
        n = int(rng.integers(2, 8))
        u = rng.uniform(-180.0, 180.0) + np.r_[0.0, np.cumsum(rng.uniform(-179.5, 179.5, n - 1))]
        lon = (u + 180.0) % 360.0 - 180.0
        line = np.column_stack([lon, rng.uniform(-70.0, 70.0, n), rng.uniform(-500.0, 0.0, n)])[:, :cols]
        k = _crossings(lon)
        assert crosses(lon) is (k > 0)
        pieces = cut_line(line)
        assert len(pieces) == k + 1
        for p in pieces:
            assert p.shape[1] == cols
            assert np.all(np.abs(p[:, 0]) <= 180.0) and np.all(np.abs(np.diff(p[:, 0])) < 180.0)
        cat = np.vstack(pieces)  # each cut's two points one point, 360° apart: the unwrapped pieces in a row
        got = shapely.LineString(np.column_stack([_unwrap(cat[:, 0]), cat[:, 1]]))
        want = shapely.LineString(np.column_stack([_unwrap(lon), line[:, 1]]))
        assert got.hausdorff_distance(want) < 1e-9
        np.testing.assert_allclose(join_line(pieces), line, rtol=0.0, atol=1e-12)


def test_a_step_just_over_180_degrees_is_the_short_way_across():
    """90° to -90.5°: 180.5° eastward on the map, 179.5° the short way (across ±180°); 90° to -89.5° is not."""
    assert crosses([90.0, -90.5]) and crosses([-90.5, 90.0]) and not crosses([90.0, -89.5])
    pieces = cut_line([[90.0, 0.0, -10.0], [-90.5, 1.0, -20.0]])
    assert len(pieces) == 2
    np.testing.assert_allclose(pieces[0][-1], [180.0, 90.0 / 179.5, -10.0 - 10.0 * 90.0 / 179.5], atol=1e-12)
    np.testing.assert_allclose(pieces[1][0], [-180.0, 90.0 / 179.5, -10.0 - 10.0 * 90.0 / 179.5], atol=1e-12)


def test_an_empty_or_one_point_line_is_one_piece():
    for n in (0, 1):
        line = np.full((n, 3), 179.9)
        pieces = cut_line(line)
        assert len(pieces) == 1 and pieces[0].shape == (n, 3)


@pytest.mark.parametrize(("end", "start"), [
    ([170.0, 10.0, -50.0], [170.0, 10.0, -50.0]),      # a shared end off the antimeridian (parts of one route)
    ([180.0, 10.0, -50.0], [170.0, 10.0, -50.0]),      # only the first on it
    ([170.0, 10.0, -50.0], [-180.0, 10.0, -50.0]),     # only the second on it
    ([180.0, 10.0, -50.0], [-180.0, 11.0, -50.0]),     # both on it, the second further north
    ([180.0, 11.0, -50.0], [-180.0, 10.0, -50.0]),     # both on it, the second further south
    ([180.0, 10.0, -50.0], [-180.0, 10.0, -80.0]),     # both on it at one latitude, 30 m apart in depth (a dive)
])
def test_pieces_that_meet_but_are_not_a_cut_are_joined_end_to_end(end, start):
    a = np.array([[169.0, 9.0, -40.0], end])
    b = np.array([start, [171.0, 12.0, -60.0]])
    np.testing.assert_array_equal(join_line([a, b]), np.vstack([a, b]))


def test_empty_pieces_are_skipped_and_a_cut_across_them_is_not_joined():
    a = np.array([[179.0, 10.0, -50.0], [180.0, 10.5, -50.0]])
    b = np.array([[-180.0, 10.5, -50.0], [-179.0, 11.0, -50.0]])
    empty = np.empty((0, 3))
    np.testing.assert_array_equal(join_line([a, empty, b]), np.vstack([a, b]))  # not adjacent: not a cut
    np.testing.assert_array_equal(join_line([a, b, empty]), np.vstack([a[:1], b[1:]]))
    np.testing.assert_array_equal(join_line([empty, a, b]), np.vstack([a[:1], b[1:]]))


def _area_unwrapped(ring: np.ndarray) -> float:
    return float(shapely.Polygon(np.column_stack([_unwrap(np.r_[ring[:, 0]]), ring[:, 1]])).area)


@pytest.mark.parametrize(("lon", "lat"), [
    ([179.9, -179.8, -179.8, 179.9], [10.0, 10.0, 10.5, 10.5]),     # from the east side, eastward
    ([-179.9, 179.8, 179.8, -179.9], [10.0, 10.0, 10.5, 10.5]),     # from the west side, westward
    ([-179.2, -179.2, 179.3, 179.3], [-60.0, -59.0, -59.0, -60.0]),  # far across (0.8 and 0.7 degrees), clockwise
    ([179.95, -179.9, -179.9, 179.95], [0.0, 0.0, 0.3, 0.3]),       # from the equator north
])
def test_rings_either_way_across_are_cut_in_two_and_joined_back(lon, lat):
    lon, lat = np.asarray(lon), np.asarray(lat)
    area = _area_unwrapped(np.column_stack([lon, lat]))
    parts = cut_ring(lon, lat)
    assert len(parts) == 2
    for p in parts:
        assert np.all(np.abs(p[:, 0]) <= 180.0) and np.all(np.abs(np.diff(np.r_[p[:, 0], p[:1, 0]])) < 180.0)
    assert sum(shapely.Polygon(p).area for p in parts) == pytest.approx(area, rel=1e-9)
    rolled = [[np.roll(p, s, axis=0) for p in parts] for s in range(4)]  # each piece from any of its vertices
    for rings in (*rolled, [np.vstack([p, p[:1]]) for p in parts], parts[::-1]):  # open, closed, either first
        back = join_rings(rings)
        assert back.shape == (4, 2)
        assert np.all(back[:, 0] >= -180.0) and np.all(back[:, 0] < 180.0)  # the documented range
        assert _area_unwrapped(back) == pytest.approx(area, rel=1e-9)
        got = {(round(float(x), 9), round(float(y), 9)) for x, y in back}
        assert got == {(round(float(x), 9), round(float(y), 9)) for x, y in zip(lon, lat, strict=True)}


def test_one_ring_is_returned_open_and_without_its_altitude():
    ring = np.array([[10.0, 1.0, -5.0], [11.0, 1.0, -5.0], [11.0, 2.0, -5.0], [10.0, 2.0, -5.0]])
    for r in (ring, np.vstack([ring, ring[:1]])):  # open, closed (as KML and GeoJSON write a ring)
        np.testing.assert_array_equal(join_rings([r]), ring[:, :2])
        np.testing.assert_array_equal(join_rings([r[:, :2]]), ring[:, :2])


def test_rings_that_do_not_meet_give_the_largest():
    small = np.array([[10.0, 1.0], [10.5, 1.0], [10.5, 1.5], [10.0, 1.5]])
    large = np.array([[20.0, 1.0], [22.0, 1.0], [22.0, 3.0], [20.0, 3.0]])
    for rings in ([small, large], [large, small]):
        back = join_rings(rings)
        assert shapely.Polygon(back).area == pytest.approx(4.0, rel=1e-12)
        assert shapely.Polygon(back).equals(shapely.Polygon(large))
