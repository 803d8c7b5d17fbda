"""Issue 56.5: the tail after a long flight.  The flown energy asked the current once per one-second block
of the track (61 200 calls for a 17 h flight, each a Python call); ``CurrentField.velocity_at`` answers the
whole track at once.  Oracle: the per-point :meth:`velocity` the old loop called, value for value."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.endurance.flown import flown_energy
from auvplan.endurance.power import WH, EnergyModel
from auvplan.world import Bounds, GriddedCurrent, LambOseenVortices, UniformCurrent, World
from auvplan.world.currents.ensemble import MeanCurrent, ShiftedCurrent


def _gridded(seed: int) -> GriddedCurrent:
    rng = np.random.default_rng(seed)
    x = np.cumsum(rng.uniform(200, 900, 9)) - 3000  # uneven, non-square: 9 x 7, 3 levels, 5 times
    y = np.cumsum(rng.uniform(300, 700, 7)) - 2000
    z = np.array([-200.0, -60.0, 0.0])
    t = np.array([0.0, 3600.0, 9000.0, 20000.0, 70000.0])
    shape = (t.size, z.size, y.size, x.size)
    return GriddedCurrent(x, y, z, rng.normal(0, 0.4, shape), rng.normal(0, 0.4, shape), rng.normal(0, 0.01, shape),
                          t, name="random")


def _points(n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    p = np.column_stack([rng.uniform(-3500, 4000, n), rng.uniform(-2500, 2500, n), rng.uniform(-250, 5, n)])
    return p, np.sort(rng.uniform(-100.0, 80000.0, n))  # past both ends of the time axis too


def _tides() -> object:
    """juan-de-fuca-tides' field: 78 NOAA station depths at 20 sites (the built-in station file)."""
    from auvplan.io.data.geo import LocalFrame
    from auvplan.io.data.ocean.tides import load_tidal_current, parse_start_time

    return load_tidal_current("juan-de-fuca", LocalFrame(48.08, -124.12), parse_start_time("2024-03-01T00:00:00Z"))


@pytest.mark.parametrize("make", ["gridded", "vortices", "uniform", "shifted", "mean", "tides"])
def test_velocity_at_is_the_per_point_velocity(make: str) -> None:
    fields = {
        "gridded": lambda: _gridded(1),
        "vortices": lambda: LambOseenVortices([(0.0, 0.0), (900.0, -400.0)], [3000.0, -1500.0], [300.0, 150.0]),
        "uniform": lambda: UniformCurrent((0.3, -0.1, 0.0)),
        "shifted": lambda: ShiftedCurrent(_gridded(2), 5000.0),
        "mean": lambda: MeanCurrent((_gridded(3), _gridded(4))),
        "tides": _tides,
    }
    field = fields[make]()
    p, t = _points(400, 7)
    if make == "tides":  # the strait's stations, times over three days (three minute tables)
        b = np.array([[0.0, 68000.0], [8000.0, 36000.0], [-200.0, -5.0]])  # the scenario's bounds
        p = b[:, 0] + (b[:, 1] - b[:, 0]) * (p - p.min(0)) / np.ptp(p, axis=0)
        t = np.sort(np.random.default_rng(3).uniform(0.0, 3 * 86400.0, p.shape[0]))
    got = field.velocity_at(p, t)
    want = np.array([field.velocity(q, float(s)) for q, s in zip(p, t)]).reshape(-1, 3)
    assert got.shape == (p.shape[0], 3)
    if make == "tides":  # one matrix product for all points: the sums in another order, round-off only
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-15)
    else:
        np.testing.assert_array_equal(got, want)


def test_flown_energy_matches_the_block_by_block_sum_on_a_long_track() -> None:
    field = _gridded(5)
    world = World(Bounds(field.x[0], field.x[-1], field.y[0], field.y[-1], -250, 0), currents=field)
    t = np.arange(0.0, 61200.0, 0.5)  # 17 h at 2 Hz
    rng = np.random.default_rng(11)
    p = np.column_stack([np.cumsum(rng.normal(0, 0.7, t.size)) % 6000 - 2500,
                         np.cumsum(rng.normal(0, 0.7, t.size)) % 4000 - 1800, -50 + 0 * t])
    model = EnergyModel(hotel_w=80.0, k=30.0)
    got = flown_energy(world, t, p, model, block_s=1.0)
    # the old per-block evaluation: one velocity call per block's middle
    tb, pb = t[::2], p[::2]
    tb, pb = np.r_[tb, t[-1]], np.vstack([pb, p[-1]])
    dt = np.diff(tb)
    mid_p, mid_t = 0.5 * (pb[:-1] + pb[1:]), 0.5 * (tb[:-1] + tb[1:])
    cur = np.array([field.velocity(q, s) for q, s in zip(mid_p, mid_t)]).reshape(-1, 3)
    water = np.linalg.norm(np.diff(pb, axis=0) / np.where(dt > 0, dt, 1.0)[:, None] - cur, axis=1)
    water = np.where(dt > 0, water, 0.0)
    want = np.r_[0.0, np.cumsum(np.asarray(model.power(water)) * dt / WH)]
    np.testing.assert_array_equal(got.cumulative_wh, want)
    assert got.energy_wh > 0
