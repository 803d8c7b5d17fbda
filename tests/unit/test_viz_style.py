"""The shared colour convention and the chart helpers (oracles: the colour map's own definition,
round numbers by hand), and the matplotlib figures against stored baseline images."""

from __future__ import annotations

import os
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.colors import LinearSegmentedColormap, to_rgb
from matplotlib.testing.compare import compare_images

from auvplan._types import Status
from auvplan.sim import RunRecord, SimResult
from auvplan.viz import plots
from auvplan.viz.chart import degree_label, nice_step
from auvplan.viz.scene3d import hms, vertical_exaggeration
from auvplan.viz.style import BATHY_CMAP, LAND_COLORS, bathymetry_cmap, bathymetry_colorscale, bathymetry_stops
from auvplan.world import Bounds, Sphere, Terrain, World

BASELINE = Path(__file__).parents[1] / "baseline"


def _rgb(hexes):
    return np.array([to_rgb(h) for h in hexes])


def test_bathymetry_scale_breaks_at_sea_level_with_water_below_and_land_above():
    p, c = bathymetry_stops(-3000.0, 1000.0)
    at0 = np.flatnonzero(np.isclose(p, 0.75))
    assert at0.size == 2  # two stops at 0 m: a hard break
    assert np.all(np.diff(p) >= 0) and p[0] == 0.0 and p[-1] == 1.0
    water, land = _rgb(c[: at0[0] + 1]), _rgb(c[at0[1]:])
    # Water stops are colours of topo's water half short of its pale green (a shelf must not read as
    # land); land stops are the chart's sand-to-brown ramp, from its first colour to its last.
    lower = BATHY_CMAP(np.linspace(0, 0.38, 400))[:, :3]
    ramp = LinearSegmentedColormap.from_list("land", list(LAND_COLORS))(np.linspace(0, 1, 400))[:, :3]

    def nearest(a, table):
        return np.min(np.linalg.norm(a[:, None] - table[None], axis=2), axis=1)

    assert nearest(water, lower).max() < 0.02 and nearest(land, ramp).max() < 0.02
    assert np.allclose(land[0], to_rgb(LAND_COLORS[0]), atol=0.01) and np.allclose(land[-1], to_rgb(LAND_COLORS[-1]),
                                                                                     atol=0.01)
    # the shallowest water and the lowest land are far apart (no pale-green shelf beside olive land)
    assert np.linalg.norm(water[-1] - land[0]) > 0.3
    assert nearest(land, lower).min() > 0.1  # no land stop is a water colour


def test_offshore_scenes_never_use_coastal_or_land_colours():
    p, c = bathymetry_stops(-3100.0, -2300.0)
    assert np.all(np.diff(p) > 0)
    pale = BATHY_CMAP(np.linspace(0.41, 1.0, 200))[:, :3]
    d = np.min(np.linalg.norm(_rgb(c)[:, None] - pale[None], axis=2), axis=1)
    assert d.min() > 0.0 and d[:-1].min() > 0.01


def test_plotly_and_matplotlib_views_give_one_colour_per_depth():
    lo, hi = -2500.0, 300.0
    scale = bathymetry_colorscale(lo, hi)
    cmap, norm = bathymetry_cmap(lo, hi)
    pos = np.array([s[0] for s in scale])
    rgb = _rgb([s[1] for s in scale])
    for z in (-2400.0, -1200.0, -10.0, 10.0, 250.0):
        f = (z - lo) / (hi - lo)
        k = np.searchsorted(pos, f, side="right") - 1
        w = (f - pos[k]) / (pos[k + 1] - pos[k])
        plotly_rgb = (1 - w) * rgb[k] + w * rgb[k + 1]
        assert np.allclose(cmap(norm(z))[:3], plotly_rgb, atol=0.01), z


def test_clock_labels_scale_steps_and_degree_labels():
    assert [hms(t) for t in (0, 59.6, 3599, 3600, 4850, 90061)] == [
        "0:00:00", "0:01:00", "0:59:59", "1:00:00", "1:20:50", "25:01:01"]
    assert [nice_step(s) for s in (6000.0, 1.04, 100_000.0, 37.0)] == [1000.0, 0.2, 20_000.0, 5.0]
    assert nice_step(0.0) == 1.0  # a flat seabed still gets isobaths
    assert degree_label(158.75, "lon", 0.25) == "158.75°E"
    assert degree_label(-122.5, "lon", 0.5) == "122.5°W"
    assert degree_label(14.0, "lat", 1.0) == "14°N" and degree_label(-3.2, "lat", 0.2) == "3.2°S"


def test_vertical_exaggeration_is_round_and_targets_the_box_shape():
    w = World(Bounds(0, 100_000, 0, 50_000, -6000, 0))
    assert vertical_exaggeration(w) == 5.0  # 0.35 * 100 km / 6 km = 5.8 → 5
    assert vertical_exaggeration(World(Bounds(0, 60, 0, 60, -40, 0))) == 1.0


def _world_and_record():
    x = np.linspace(0, 4000, 41)
    X, Y = np.meshgrid(x, x)
    z = -800 + 500 * np.exp(-((X - 2000) ** 2 + (Y - 2200) ** 2) / 6e5) + 0.05 * X
    world = World(Bounds(0, 4000, 0, 4000, -900, 0), Terrain(x, x, z, name="hump"),
                  obstacles=(Sphere((1200.0, 2600.0, -500.0), 150.0),))
    t = np.linspace(0, 3000, 301)
    s = t / 3000
    pos = np.column_stack([300 + 3400 * s, 400 + 3000 * s + 300 * np.sin(np.pi * s), -600 + 100 * s])
    alt = pos[:, 2] - world.terrain.elevation(pos[:, 0], pos[:, 1])
    n = t.size
    zeros = np.zeros(n)
    sim = SimResult(status=Status.EXACT, arrived=True, t=t, position=pos, heading=zeros, speed=zeros + 1.5,
                    rudder=zeros, cross_track=zeros, route_error=zeros, progress=s * 4500, altitude=alt,
                    obstacle_distance=np.zeros((n, 1)), events=(), guidance="hybrid", wall_time_s=0.0)
    route = pos[::50]
    return world, RunRecord("baseline", 0, None, route, route[[0, 3, -1]], sim)


def _compare(fig, name: str, tmp_path: Path, tol: float = 6.0) -> None:
    out = tmp_path / f"{name}.png"
    fig.savefig(out, dpi=60)
    plt.close(fig)
    expected = BASELINE / f"{name}.png"
    if os.environ.get("AUVPLAN_UPDATE_BASELINES"):
        expected.write_bytes(out.read_bytes())
    assert expected.is_file(), f"no baseline {expected}; run with AUVPLAN_UPDATE_BASELINES=1"
    diff = compare_images(str(expected), str(out), tol=tol)
    assert diff is None, diff


@pytest.mark.parametrize("name", ["plan_view", "algorithm_paths"])
def test_matplotlib_figures_match_their_baselines(name, tmp_path):
    world, record = _world_and_record()
    if name == "plan_view":
        fig = plots.plan_view(world, record)
    else:
        fig = plots.algorithm_paths(world, {"route": record.route, "track": record.sim.position})
    _compare(fig, name, tmp_path)


def test_a_strip_of_a_plan_view_is_drawn_exaggerated_and_says_so():
    world, record = _world_and_record()
    flat = record.sim.position * np.array([1.0, 0.0, 1.0]) + np.array([0.0, 2000.0, 0.0])
    flat[:, 1] += np.linspace(0, 20, flat.shape[0])
    sim = SimResult(**{**record.sim.__dict__, "position": flat})
    fig = plots.plan_view(world, RunRecord("strip", 0, None, flat[::50], flat[:0], sim))
    ax = fig.axes[0]
    assert "exaggerated" in ax.get_title()
    plt.close(fig)
