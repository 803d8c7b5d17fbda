"""Tidal currents: harmonic prediction against pyTMD, interpolation in space and depth, scenario keys."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from auvplan.errors import AuvplanError, DataError
from auvplan.io.data.geo import LocalFrame
from auvplan.io.data.ocean.tides import load_tidal_current, parse_start_time
from auvplan.io.scenario import loader as scenario
from auvplan.world.currents.tides import predict_speed

FRAME = LocalFrame(48.08, -124.12)
# constituents whose argument conventions differ between XTide's tables and pyTMD (M1, M3, L2, OO1:
# V0+u apart by 11-280 degrees or f by 10 %): left out of both sums of the comparison
DIFFERENT = ("M1", "M3", "L2", "OO1")


@pytest.fixture(scope="module")
def field():
    return load_tidal_current("juan-de-fuca", FRAME, parse_start_time("2026-03-01T00:00:00Z"))


def _station(field, prefix):
    return next(i for i, n in enumerate(field.names) if n.startswith(prefix))


@pytest.mark.parametrize("prefix", ["Race Rocks, 4.5 mi. S of (Depth 59.7ft)",
                                    "Strait of Juan de Fuca entrance (Depth 101.8ft)",
                                    "Pillar Point, 6 mi. NNE of (Depth 73.5ft)"])
def test_prediction_matches_pytmd(field, prefix):
    """Our sum on XTide's yearly tables vs the same constants on pyTMD's astronomical arguments and
    node corrections, evaluated at every time: within 0.02 m/s (about 1.5 % of the 1.1-1.6 m/s peaks)
    over 30 days at half-hour steps (XTide holds f and u constant over a year)."""
    constituents = pytest.importorskip("pyTMD.constituents")
    tab = field.tables
    i = _station(field, prefix)
    keep = np.array([n not in DIFFERENT for n in tab.names])
    amp = field.amplitude[i] * keep
    t = field.epoch + np.arange(0.0, 30 * 86400.0, 1800.0)
    ours = predict_speed(tab, amp[None], field.greenwich_phase[i][None], field.mean[i:i + 1], t)[:, 0]
    names = [n.lower().replace("lda2", "lambda2") for n, k in zip(tab.names, keep) if k]
    pu, pf, g = constituents.arguments(t / 86400.0 + 40587.0, names, corrections="perth3")
    phase = np.radians(field.greenwich_phase[i][keep])
    ref = field.mean[i] + (pf * amp[keep] * np.cos(np.radians(g) + pu - phase)).sum(axis=1)
    assert np.abs(ref).max() > 0.8
    assert np.abs(ours - ref).max() < 0.02
    assert np.sqrt(np.mean((ours - ref) ** 2)) < 0.008


def test_station_velocity_follows_flood_and_ebb_axes(field):
    i = _station(field, "Race Rocks, 4.5 mi. S of (Depth 59.7ft)")
    t = np.arange(0.0, 86400.0, 900.0)
    v = field.station_velocity(t)[:, i]
    s = predict_speed(field.tables, field.amplitude[i:i + 1], field.greenwich_phase[i:i + 1], field.mean[i:i + 1],
                      field.epoch + t)[:, 0]
    assert np.allclose(np.hypot(v[:, 0], v[:, 1]), np.abs(s))
    axis = np.where(s[:, None] >= 0, field.flood[i], field.ebb[i])
    assert np.allclose(np.einsum("tc,tc->t", v, axis), np.abs(s))
    # the strait floods towards the east and ebbs towards the west
    assert field.flood[i][0] > 0.9 and field.ebb[i][0] < -0.9


def test_interpolation_reproduces_a_site_and_is_linear_in_depth(field):
    sharp = dataclasses.replace(field, r0=1e-3)
    i = _station(field, "Race Rocks, 4.5 mi. S of (Depth 59.7ft)")
    site = field.site[i]
    bins = np.flatnonzero(field.site == site)
    bins = bins[np.argsort(field.depth[bins])]
    x, y = field.site_xy[site]
    t = 7200.0
    vs = field.station_velocity(t)[0]
    for b in bins:
        assert np.allclose(sharp.velocity([x, y, -field.depth[b]], t)[:2], vs[b], atol=1e-9)
    mid = 0.25 * field.depth[bins[0]] + 0.75 * field.depth[bins[1]]
    assert np.allclose(sharp.velocity([x, y, -mid], t)[:2], 0.25 * vs[bins[0]] + 0.75 * vs[bins[1]], atol=1e-9)
    w = field.weights(np.random.default_rng(1).uniform([0, 8000, -200], [68000, 36000, 0], (200, 3)))
    assert np.allclose(w.sum(axis=1), 1.0) and w.min() >= 0.0


def test_sample_equals_velocity_and_respects_max_speed(field):
    p = np.random.default_rng(2).uniform([0, 8000, -150], [68000, 36000, -5], (40, 3))
    times = np.arange(0.0, 86400.0, 3600.0) + 17.3
    s = field.sample(p, times)
    v = np.stack([field.velocity(p, t) for t in times])
    # velocity() interpolates the stations linearly between predictions a minute apart
    assert np.allclose(s, v, atol=1e-5)
    assert np.all(s[..., 2] == 0.0)
    assert np.hypot(s[..., 0], s[..., 1]).max() <= field.max_speed


def test_years_outside_the_tables_are_a_data_error(field):
    late = dataclasses.replace(field, epoch=parse_start_time("2045-01-01T00:00:00Z"))
    with pytest.raises(DataError, match="outside the tables"):
        late.velocity([0.0, 0.0, -10.0], 0.0)


def test_start_time_parsing():
    assert parse_start_time("1970-01-01T00:00:00Z") == 0.0
    assert parse_start_time("1970-01-01T01:00:00+01:00") == 0.0
    assert parse_start_time("1970-01-01T00:00:10") == 10.0
    with pytest.raises(ValueError, match="ISO 8601"):
        parse_start_time("tomorrow")


@pytest.fixture(scope="module")
def tides_scenario():
    """(World, Mission) of the built-in juan-de-fuca-tides, built once for the tests below (12 s of CPU with
    numba off: its seabed's kernels run as plain Python in ``make test-nojit``)."""
    return scenario.build(scenario.load("juan-de-fuca-tides"))


def test_tidal_scenario_builds_and_needs_a_start_time(tides_scenario):
    world, mission = tides_scenario
    assert type(world.currents).__name__ == "TidalCurrent"
    assert world.currents.velocity(mission.start, 3600.0)[:2].any()
    text = scenario.resolve("juan-de-fuca-tides").read_text()
    with pytest.raises(AuvplanError, match="start_time"):
        scenario.build(scenario.loads(text.replace('start_time = "2026-06-15T00:00:00Z"\n', "")))
    with pytest.raises(AuvplanError, match=r"\[mission\].*start_time"):
        scenario.loads(text.replace("2026-06-15T00:00:00Z", "soon"))


def test_report_animates_a_tidal_current_and_not_a_steady_one(tides_scenario, salish):
    import plotly.graph_objects as go

    from auvplan.viz.scene3d import _current_frames, _currents

    world, mission = tides_scenario
    path = np.stack([mission.start, mission.goal])
    fig = go.Figure(_currents(world, path))
    times = np.linspace(2 * 3600.0, 8 * 3600.0, 7)  # the fastest frame is neither the first nor the last
    idx, v = _current_frames(fig, world, times)
    assert v.shape == (7, len(fig.data[idx].x), 3) and not np.allclose(v[0], v[3])
    peak = np.linalg.norm(v, axis=2).max(axis=1)
    assert 0 < int(np.argmax(peak)) < len(times) - 1  # a scale from one end frame only would be caught
    assert fig.data[idx].cmax == pytest.approx(peak.max())
    _, steady, _ = salish  # the session's salish-shelf (tests/conftest.py)
    assert _current_frames(go.Figure(_currents(steady, path)), steady, times) is None
