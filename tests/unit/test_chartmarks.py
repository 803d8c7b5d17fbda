"""Chart conventions (issue 40): isobath intervals from the relief, the coastline, labels that do not
collide, a minimum drawn size; the static plan view framed on the map with round colour-bar ticks and a
legend in the drawing's colours. Oracles: intervals and counts by hand, boxes by hand, the figure's own
artists."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from matplotlib.colors import to_hex

from auvplan.io.scenario import loader as sc
from auvplan.viz.chartmarks import coastline, isobath_levels, needs_marker, north_arrow, place_labels, scale_bar
from auvplan.world import Bounds, Land, Terrain, World


@pytest.mark.parametrize(("zmin", "zmax", "step", "count"), [
    (-6000.0, -200.0, 500.0, 12),      # an ocean box: every 500 m, not a blocky 1 000 m
    (-6000.0, 1200.0, 500.0, 12),      # land above 0 adds no isobath
    (-130.0, 40.0, 10.0, 13),          # a strait: every 10 m
    (-3480.0, -2460.0, 100.0, 10),     # a seamount flank
    (-47.0, -3.0, 5.0, 9),             # a shallow bay: 1, 2, 5 x 10^k only
])
def test_isobath_interval_is_round_and_follows_the_relief(zmin, zmax, step, count):
    levels, got = isobath_levels(zmin, zmax)
    assert got == step and levels.size == count
    assert np.all(levels < 0) and np.all(levels >= zmin) and np.all(levels <= zmax)
    assert np.allclose(levels / step, np.round(levels / step))
    assert np.allclose(np.diff(levels), step)


def test_no_isobath_without_water():
    assert isobath_levels(10.0, 300.0)[0].size == 0


def test_labels_take_the_first_clear_place_and_never_overlap():
    # two labels 20 px wide at the same point: the second moves to its next candidate, a third with no
    # clear candidate is left out; a box already taken (the scale bar) is avoided
    cands = [[(0.0, 0.0)], [(0.0, 0.0), (1.0, 0.0)], [(0.0, 0.0), (1.0, 0.0)], [(5.0, 5.0), (9.0, 9.0)]]
    chosen = place_labels(cands, [(20.0, 10.0)] * 4, (30.0, 30.0), pad=1.0, taken=[(140.0, 140.0, 160.0, 160.0)])
    assert chosen == [0, 1, None, 1]


def test_small_obstacles_get_a_symbol():
    assert needs_marker(30.0, 900 / 6000) and not needs_marker(300.0, 900 / 6000)  # 4.5 px vs 45 px


def test_coastline_is_the_land_boundary_or_the_zero_contour():
    x = np.linspace(0.0, 1000.0, 51)
    X, Y = np.meshgrid(x, x)
    terrain = Terrain(x, x, -50.0 + 0.1 * X)  # shore at x = 500 m
    world = World(Bounds(0, 1000, 0, 1000, -60, 60), terrain)
    lines = coastline(world, x, x, terrain.z)
    assert len(lines) == 1 and np.allclose(lines[0][:, 0], 500.0, atol=1e-6)
    land = Land(shapely.box(700.0, -100.0, 1200.0, 1200.0))
    world = World(Bounds(0, 1000, 0, 1000, -60, 60), terrain, land=land)
    shore = coastline(world, x, x, world.terrain.z)
    pts = np.vstack(shore)
    assert np.allclose(pts[:, 0], 700.0) or np.isclose(pts[:, 0], 700.0).mean() > 0.5


@pytest.mark.parametrize(("width", "length", "label"), [(10_000.0, 2000.0, "2 km"), (1_300.0, 250.0, "250 m")])
def test_scale_bar_is_a_round_fifth_of_the_width_in_the_lower_right(width, length, label):
    world = World(Bounds(-500.0, -500.0 + width, 100.0, 900.0, -60, 0))
    x0, y0, got, text = scale_bar(world)
    assert (got, text) == (length, label)  # 1, 2, 2.5, 5 x 10^k nearest width / 5, by hand
    assert x0 == pytest.approx(-500.0 + width - 0.06 * width - length) and y0 == pytest.approx(100.0 + 0.06 * 800.0)


@pytest.mark.parametrize("turn_deg", [0.0, 30.0, -75.0, 180.0])
def test_north_arrow_points_up_the_latitude_of_a_turned_frame(turn_deg):
    # a frame whose latitude grows along (sin θ, cos θ): north is that direction; without one, grid north
    world = World(Bounds(0.0, 4000.0, 0.0, 2000.0, -60, 0))
    th = np.radians(turn_deg)
    cx, cy, nx, ny = north_arrow(world, lambda x, y: (x * 0.0, 45.0 + 1e-5 * (x * np.sin(th) + y * np.cos(th))))
    assert (cx, cy) == pytest.approx((0.06 * 4000.0, 2000.0 - 0.16 * 2000.0))
    assert (nx, ny) == pytest.approx((np.sin(th), np.cos(th)), abs=1e-9)
    assert north_arrow(world, None)[2:] == (0.0, 1.0)


def test_static_plan_view_is_framed_on_the_map_and_dressed_as_a_chart():
    from matplotlib.collections import LineCollection

    from auvplan._types import Status
    from auvplan.io.data.geo import LocalFrame
    from auvplan.sim import RunRecord, SimResult
    from auvplan.viz import plots

    world, mission = sc.build(sc.load("dynamic-terrain"))
    t = np.linspace(0.0, 4000.0, 201)
    start, goal = np.asarray(mission.start), np.asarray(mission.goal)
    pos = start + (goal - start) * (t / t[-1])[:, None]
    alt = pos[:, 2] - world.terrain.elevation(pos[:, 0], pos[:, 1])
    z = np.zeros(t.size)
    sim = SimResult(status=Status.EXACT, arrived=True, t=t, position=pos, heading=z, speed=z + 1.5, rudder=z,
                    cross_track=z, route_error=z, progress=t * 1.5, altitude=alt,
                    obstacle_distance=np.zeros((t.size, 0)),
                    events=(), guidance="hybrid", wall_time_s=0.0)
    record = RunRecord("dynamic-terrain", 0, None, pos[::50], pos[[0, -1]], sim)
    frame = LocalFrame(*world.origin)
    fig = plots.plan_view(world, record, frame.inverse)
    ax = fig.axes[0]
    b = world.bounds
    assert ax.get_xlim() == (b.xmin, b.xmax) and ax.get_ylim() == (b.ymin, b.ymax)
    texts = [t.get_text() for t in ax.texts]
    assert any(t.endswith("°E") for t in texts) and any(t.endswith("°N") for t in texts)
    assert "N" in texts and any(t.endswith("km") or t.endswith(" m") for t in texts)
    seabed_bar = fig.axes[-1]
    ticks = seabed_bar.get_yticks()
    assert ticks.size >= 3 and np.allclose(ticks, np.round(ticks, -1))  # round ticks, not −2275.6
    handle = next(h for h in ax.get_legend().legend_handles if h.get_label() == "track (colour: altitude)")
    track = next(c for c in ax.collections if isinstance(c, LineCollection) and c.get_array() is not None)
    drawn = {to_hex(c) for c in track.to_rgba(track.get_array())}
    assert to_hex(handle.get_color()) in drawn


def _flight():
    from auvplan._types import Status
    from auvplan.sim import RunRecord, SimResult

    t = np.linspace(0.0, 600.0, 61)
    pos = np.column_stack([t, 0 * t, -40.0 - 0.01 * t])
    seabed = -100.0 + 0.05 * t  # rises under the vehicle
    z = np.zeros(t.size)
    sim = SimResult(status=Status.EXACT, arrived=True, t=t, position=pos, heading=z, speed=z + 1.0, rudder=z,
                    cross_track=z, route_error=z, progress=t, altitude=pos[:, 2] - seabed,
                    obstacle_distance=np.zeros((t.size, 0)), events=(), guidance="hybrid", wall_time_s=0.0)
    return RunRecord("flight", 0, None, pos[[0, -1]], pos[:0], sim), -seabed


def test_profiles_draw_the_seabed_under_the_depth_and_the_altitude_limit():
    from auvplan.viz import plots
    from auvplan.viz.report import figure_profiles

    record, seabed_depth = _flight()
    fig = figure_profiles(record, 20.0)
    seabed = next(t for t in fig.data if t.name == "seabed")
    assert np.allclose(seabed.y, seabed_depth[: len(seabed.y)]) and seabed.yaxis == "y"
    limit = next(t for t in fig.data if t.name == "min_altitude_m")
    assert limit.yaxis == "y2" and list(limit.y) == [20.0, 20.0]
    static = plots.profiles(record, 20.0)
    depth_lines = {ln.get_label(): ln for ln in static.axes[0].lines}
    assert np.allclose(depth_lines["seabed"].get_ydata(), seabed_depth)
    assert any(np.allclose(ln.get_ydata(), 20.0) for ln in static.axes[1].lines)
