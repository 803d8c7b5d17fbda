"""``validate``'s survey checks (``io.results.survey``: the area over the data and under water, the swath the size
check estimates, the samples it takes) worked by hand on flat seabeds far from the origin -- the cases wave 13's
tests, which compare the numpy bound's path with the compiled one, could not tell (a change made to both paths at
once; found by mutation, docs/mutants.md section 5)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from auvplan.errors import ScenarioError
from auvplan.io.results import survey as sv
from auvplan.survey.lines.placement import LineParams
from auvplan.survey.lines.swath import Sensor
from auvplan.survey.mission import SurveyParams
from auvplan.world import Bounds, Margins, Terrain, World

X0, Y0 = 600_000.0, -4_310_000.0  # the grid's corner: far from zero, as a UTM-like frame


def _flat(depth: float, min_depth: float = 0.0, plateau: bool = False, y0: float = Y0) -> World:
    """A flat seabed ``depth`` m deep on 500 m x 250 m cells over 40 x 20 km; with ``plateau``, the nodes of a
    2 x 2 km square at (X0 + 10 km, Y0 + 10 km) exactly at the surface."""
    x, y = X0 + 500.0 * np.arange(81), y0 + 250.0 * np.arange(81)
    z = np.full((y.size, x.size), -depth)
    if plateau:
        z[40:49, 20:25] = 0.0
    return World(Bounds(x[0], x[-1], y[0], y[-1], -1000.0, 0.0), Terrain(x, y, z, name="flat"),
                 margins=Margins(min_depth=min_depth))


def _box(x: float, y: float, w: float, h: float, y0: float = Y0) -> shapely.Polygon:
    return shapely.box(X0 + x, y0 + y, X0 + x + w, y0 + y + h)


@pytest.mark.parametrize(("depth", "min_depth", "ok"), [
    (13.0, 12.0, True), (12.0, 12.0, False), (10.0, 12.0, False), (0.5, 0.0, True), (0.0, 0.0, False),
])
def test_the_area_is_under_water_below_the_sensor_by_hand(depth, min_depth, ok):
    """A flat seabed ``depth`` m deep under a sensor held ``min_depth`` m deep: the area passes only with water
    under the sensor (a seabed at the sensor's own depth, or at the surface, does not)."""
    call = lambda: sv._check_seabed(_box(5000.0, 5000.0, 4000.0, 4000.0), _flat(depth, min_depth), "s.toml")  # noqa: E731
    if ok:
        call()
        return
    with pytest.raises(ScenarioError, match=rf"^s\.toml area: the seabed at \(\d+, -\d+\) m is {0.0 - depth:.1f} m, "
                                            r"not under water below the sensor \((\d+) of \1 sampled points\)$"):
        call()


@pytest.mark.parametrize("side", ["west", "east", "south", "north", None])
def test_an_area_over_the_data_to_its_edges_passes_and_a_metre_beyond_any_edge_does_not(side):
    """The grid's own extent is over its data; one metre past any one side is not."""
    world = _flat(100.0)
    x0, x1, y0, y1 = world.terrain.extent
    grow = {"west": (1.0, 0, 0, 0), "east": (0, 1.0, 0, 0), "south": (0, 0, 1.0, 0), "north": (0, 0, 0, 1.0)}
    dw, de, ds, dn = grow.get(side, (0, 0, 0, 0))
    area = shapely.box(x0 - dw, y0 - ds, x1 + de, y1 + dn)
    if side is None:
        sv._check_seabed(area, world, "s.toml")
        return
    with pytest.raises(ScenarioError, match=r"^s\.toml area x \[.*\] m: beyond the terrain's data x \["):
        sv._check_seabed(area, world, "s.toml")


def _samples(monkeypatch, area: shapely.Polygon, y0: float) -> tuple[np.ndarray, np.ndarray]:
    seen: list[tuple[np.ndarray, np.ndarray]] = []
    real = sv._seabed_bounds

    def spy(world, x, y):  # noqa: ANN001, ANN202
        seen.append((np.asarray(x), np.asarray(y)))
        return real(world, x, y)

    monkeypatch.setattr(sv, "_seabed_bounds", spy)
    sv._check_seabed(area, _flat(100.0, y0=y0), "s.toml")
    assert len(seen) == 1
    return seen[0]


@pytest.mark.parametrize("y0", [Y0, -Y0], ids=["south", "north"])  # the frame's y far below or above zero
@pytest.mark.parametrize(("w", "h", "ring", "inside", "step"), [
    (4000.0, 4000.0, 201, 39 * 39, 100.0),  # compact: the ring every sqrt(A) / 50 = 80 m, a lattice of sqrt(A) / 40
    (50.0, 50.0, 201, 39 * 39, 1.25),  # the ring's step never under 1 m: 50 m sides in 50 steps
    (20000.0, 100.0, 2 * 708 + 2 * 4 + 1, 399, 50.0),  # 200:1: ring every 28.3 m; lattice step 20 km / 400
])
def test_the_seabed_check_samples_the_ring_and_a_lattice_inside(monkeypatch, w, h, ring, inside, step, y0):
    """The sampled points: the area's outline divided every max(sqrt(A) / 50, 1) m (shapely.segmentize: each side
    in equal parts), then the lattice from the area's corner at the step max(sqrt(A) / 40, longest side / 400)
    strictly inside; counted by hand, and each on its place."""
    area = _box(1000.0, 2000.0, w, h, y0)
    px, py = _samples(monkeypatch, area, y0)
    seg = max(math.sqrt(w * h) / 50.0, 1.0)
    n_ring = 2 * math.ceil(w / seg) + 2 * math.ceil(h / seg) + 1
    assert n_ring == ring and px.size == ring + inside
    rx, ry = px[:ring], py[:ring]
    assert np.all(shapely.intersects_xy(area.exterior, rx, ry))  # on the outline, which it follows closely
    assert np.hypot(np.diff(rx), np.diff(ry)).max() <= seg * (1 + 1e-12)
    gx, gy = px[ring:] - (X0 + 1000.0), py[ring:] - (y0 + 2000.0)
    assert np.all(shapely.contains_xy(area, px[ring:], py[ring:]))
    assert np.allclose(gx / step, np.round(gx / step), atol=1e-6) and np.allclose(gy / step, np.round(gy / step),
                                                                                 atol=1e-6)


def _params(sensor: Sensor, overlap_max: float = 0.3) -> SurveyParams:
    return SurveyParams(shapely.box(0, 0, 1, 1), sensor, LineParams(overlap_max=overlap_max))


def test_the_swath_estimate_by_hand():
    """A 120 deg multibeam at the surface over 50, 100 and 200 m of water reaches d tan 60 deg a side: the spacing
    is the harmonic mean of 2 d tan 60 (1 - 0.3), the swath 2 x 200 tan 60; a side-scan of 150 m on an AUV 20 m
    up reaches sqrt(150^2 - 20^2) everywhere."""
    depth = np.array([50.0, 100.0, 200.0])
    spacing, swath = sv._swath(_params(Sensor("multibeam", 120.0, 0.0, "surface")), depth)
    t = math.tan(math.radians(60.0))
    assert spacing == pytest.approx(3.0 / sum(1.0 / (2.0 * d * t * 0.7) for d in depth), rel=1e-12)
    assert swath == pytest.approx(400.0 * t, rel=1e-12)
    spacing, swath = sv._swath(_params(Sensor("sidescan", 90.0, 150.0, "auv", 20.0), 0.25), depth)
    reach = math.sqrt(150.0**2 - 20.0**2)
    assert spacing == pytest.approx(2.0 * reach * 0.75, rel=1e-12) and swath == pytest.approx(2.0 * reach, rel=1e-12)


def test_a_sample_on_the_surface_is_left_out_of_the_size_estimate_as_one_on_land():
    """A 2 x 2 km plateau exactly at the surface inside a survey area 100 m deep: its samples (depth -0.0) are not
    water, as those of the same plateau 1 m above the surface are not: both pass the size check alike (a zero
    depth read as water gives a zero spacing and an area of ~1e300 lines)."""
    area = _box(8000.0, 8000.0, 6000.0, 6000.0)
    sensor = Sensor("multibeam", 120.0, 0.0, "surface")
    for lift in (0.0, 1.0):
        world = _flat(100.0, plateau=True)
        if lift:
            z = world.terrain.z.copy()
            z[z == 0.0] = lift
            world = World(world.bounds, Terrain(world.terrain.x, world.terrain.y, z, name="flat"))
        params = SurveyParams(area, sensor, LineParams(overlap_max=0.3, station_m=25.0, step_m=5.0))
        if not lift:  # the bound cannot tell a sample at exactly 0: the compiled seabed decides
            assert sv._swath_bounds(params, world, *_inside(area)) is None
        sv.check_survey_size(params, world, "s.toml: [survey]")


def _inside(area: shapely.Polygon) -> tuple[np.ndarray, np.ndarray]:
    x0, y0, x1, y1 = area.bounds
    gx, gy = np.meshgrid(np.linspace(x0, x1, 48), np.linspace(y0, y1, 48))
    keep = shapely.contains_xy(area, gx, gy)
    return gx[keep], gy[keep]
