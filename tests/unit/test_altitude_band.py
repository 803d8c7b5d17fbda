"""The altitude band of a terrain-following mission in the run's output (issue 49): ``metrics.json`` and the
summary carry the mission's and the flight's altitude against ``follow_altitude_m ± band``."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from auvplan.cli.run import describe_altitude
from auvplan.guidance.mission.fit import AltitudeBand
from auvplan.io.results.records import write_run
from auvplan.sim import RunRecord
from auvplan.sim.band import altitude_band_metrics
from auvplan.world.terrain import Terrain

# a flat seabed 100 m deep; the mission 20 m above it for 100 m, then climbing to 40 m over the next 100 m
FLAT = Terrain(np.linspace(-50.0, 250.0, 61), np.linspace(-50.0, 50.0, 21), np.full((21, 61), -100.0))
ROUTE = np.array([[0.0, 0.0, -80.0], [100.0, 0.0, -80.0], [200.0, 0.0, -60.0]])
BAND = AltitudeBand(20.0, 1.0, 0.5, (1,), 19.0, 0.0)


def test_planned_and_flown_altitude_figures_by_hand() -> None:
    """Planned (length-weighted, 0.5 m samples): min 20, max 40, RMS² = ∫dev² / L with dev 0 on the flat leg
    and 0..20 linear over the climb of L₂ = √(100² + 20²): L₂ · 20²/3 / (100 + L₂); within the band on the flat
    leg and the climb's first 1/20.  Flown: 0.3 m above the mission wherever sampled; where the mission is in
    the band (progress ≤ 99 m of the samples) the RMS is exactly 0.3 m."""
    m = altitude_band_metrics(FLAT, ROUTE, BAND, ds=0.5)
    l2 = math.hypot(100.0, 20.0)
    assert m["altitude_target_m"] == 20.0 and m["altitude_band_m"] == 1.0 and m["altitude_band_legs"] == 1
    assert m["altitude_min_m"] == pytest.approx(20.0, abs=1e-9)
    assert m["altitude_max_m"] == pytest.approx(40.0, abs=0.05)
    assert m["altitude_rms_m"] == pytest.approx(math.sqrt(l2 * 400.0 / 3.0 / (100.0 + l2)), rel=1e-4)
    assert m["altitude_band_held_fraction"] == pytest.approx((100.0 + l2 / 20.0) / (100.0 + l2), abs=2e-3)
    progress = np.r_[np.arange(0.0, 100.0), np.arange(150.0, 201.0)]  # horizontal progress along the route
    planned = np.where(progress <= 100.0, 20.0, 20.0 + 0.2 * (progress - 100.0))
    m = altitude_band_metrics(FLAT, ROUTE, BAND, (progress, planned + 0.3))
    assert m["flown_altitude_rms_m"] == pytest.approx(0.3, abs=1e-9)
    assert m["flown_altitude_band_held_fraction"] == 1.0
    assert (m["flown_altitude_min_m"], m["flown_altitude_max_m"]) == pytest.approx((20.3, 40.3), abs=1e-9)
    off = altitude_band_metrics(FLAT, ROUTE, BAND, (progress, planned + np.where(progress < 50.0, 2.0, 0.0)))
    assert off["flown_altitude_band_held_fraction"] == pytest.approx(0.5, abs=1e-9)  # 50 of the 100 held samples
    assert off["flown_altitude_rms_m"] == pytest.approx(math.sqrt(0.5 * 4.0), abs=1e-9)


def test_the_band_figures_reach_metrics_json_run_json_and_the_summary(tmp_path: Path) -> None:
    fig = altitude_band_metrics(FLAT, ROUTE, BAND, (np.arange(0.0, 100.0), np.full(100, 20.5)))
    write_run(tmp_path, RunRecord("flat", 1, None, ROUTE, ROUTE[[0, -1]], None, altitude=fig))
    metrics = json.loads((tmp_path / "metrics.json").read_text())
    assert {k: metrics[k] for k in fig} == pytest.approx(fig)
    assert json.loads((tmp_path / "run.json").read_text())["altitude"] == pytest.approx(fig)
    line = describe_altitude(fig)
    assert line.startswith("  altitude 20 ± 1 m: mission 20.0-39.5 m") and "RMS off target 0.50 m" in line  # (the
    # last 5 m sample's midpoint: 20 + 20 · 20.5 / 21 m)
    assert "(1 leg out where the pitch limit forces it)" in line
