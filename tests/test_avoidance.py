"""Issue #21: predictive avoidance of fast moving obstacles, escapes before deadlock, the document variant pinned."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from auvplan.bench import perturb_moving
from auvplan.io import scenario as sc
from auvplan.sim import simulate

PIN = json.loads((Path(__file__).parent / "data" / "dynamic_terrain_apf_pin.json").read_text())


@pytest.mark.parametrize("seed", [0, 3])
def test_document_apf_reproduces_pinned_dynamic_terrain_runs(seed):
    """Document 004's APF (``avoidance = "apf"``) flies the pinned dynamic-terrain route exactly as before #21."""
    w, m = sc.build(sc.load("dynamic-terrain"))
    route, keys = np.array(PIN["route"]), np.array(PIN["keys"])
    r = simulate(perturb_moving(w, seed), m, route=route, rng=seed, keys=keys, avoidance="apf")
    pin = PIN[f"seed{seed}"]
    met = r.metrics
    assert r.arrived and met["collisions"] == 0 and met["escapes"] == 0
    assert met["duration_s"] == pytest.approx(pin["duration_s"], abs=1e-9)
    assert r.decision_steps == pin["decisions"]
    assert met["distance_m"] == pytest.approx(pin["distance_m"], rel=1e-6)
    assert np.allclose(met["obstacle_min_distances_m"], pin["obstacle_min_distances_m"], atol=1e-3)
    assert np.allclose(r.position[-1], pin["final"], atol=1e-3)
