"""Issue #35.1 (wave 5): the seeding lattice's taut path as a second polish candidate, the polish's
cheaper levels and kernels, and the release-code peer of benchmarks/hard.py."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from benchmarks.release_peer import portable_scenario

from auvplan.io.scenario import loader as sc
from auvplan.path import densify
from auvplan.path.flyable import merge_close
from auvplan.planners import plan
from auvplan.planners.swarm import polish
from auvplan.sim import planning_problem

CHAGOS_BEST = 489_233.0
"""chagos-banks' best known cost (the converged lattice reference, docs/bench_hard.md)."""


@pytest.fixture(scope="module")
def chagos():
    world, mission = sc.build(sc.load("chagos-banks"))
    return planning_problem(world, mission), replace(mission.planner, budget=10_000)


def test_lattice_candidate_takes_the_saddle_the_splines_miss(chagos, monkeypatch):
    """Seed 1 of chagos-banks: the spline, polished, passes beside the narrow saddle before the goal
    (+0.36 % from the best known); the seeding lattice's taut path, polished, threads it and wins:
    within +0.1 % of the best known, free, the budget spent exactly.  Without the lattice candidate the
    same seed ends more than 0.2 % above it (the candidate is what closes the gap).  The lifted candidate
    (wave 7) is left out of that second run: alone it brings this seed to +0.13 %, still above the lattice's."""
    prob, spec = chagos
    r = plan(prob, spec, rng=1)
    assert r.status.ok and r.evaluations == spec.budget
    assert "from the seeding lattice's taut path" in r.message
    assert prob.world.path_free(r.path)
    assert r.cost <= CHAGOS_BEST * 1.001
    monkeypatch.setattr(polish.LatticeCorridor, "candidate", lambda self, result: None)
    monkeypatch.setattr(polish, "_lifted_plan", lambda *a: None)
    alone = plan(prob, spec, rng=1)
    assert alone.cost > CHAGOS_BEST * 1.002 and r.cost < alone.cost


def test_polish_is_never_worse_than_either_candidate(chagos):
    """The returned cost is at most the spline's (polish off) on the same seed."""
    prob, spec = chagos
    for seed in (0, 2):
        base = plan(prob, replace(spec, polish=0), rng=seed)
        new = plan(prob, spec, rng=seed)
        assert new.cost <= base.cost and new.status.ok


def _merge_close_by_definition(p: np.ndarray, tol: float) -> np.ndarray:
    keep = [0]
    for i in range(1, len(p)):
        if np.linalg.norm(p[i] - p[keep[-1]]) >= tol:
            keep.append(i)
    if keep[-1] != len(p) - 1:
        if len(keep) > 1:
            keep[-1] = len(p) - 1
        else:
            keep.append(len(p) - 1)
    return np.asarray(keep)


def test_merge_close_matches_its_definition():
    """The float loop keeps exactly the vertices the numpy-row definition keeps (clustered points)."""
    rng = np.random.default_rng(3)
    for _ in range(20):
        p = np.cumsum(rng.exponential(1.0, size=(200, 3)) * rng.choice([1e-6, 1.0, 5.0], size=(200, 1)), axis=0)
        for tol in (0.5, 2.0, 8.0):
            assert np.array_equal(merge_close(p, tol), _merge_close_by_definition(p, tol))


def test_densify_matches_the_per_segment_aranges():
    """The vectorised parameters are bit for bit the per-segment ``arange(k) / k``."""
    rng = np.random.default_rng(5)
    p = rng.normal(size=(40, 3)) * 1000.0
    out = densify(p, 137.0)
    seg = np.linalg.norm(np.diff(p, axis=0), axis=1)
    n = np.maximum(np.ceil(seg / 137.0).astype(int), 1)
    t = np.concatenate([np.arange(k) / k for k in n])
    i = np.repeat(np.arange(len(n)), n)
    assert np.array_equal(out, np.vstack([p[i] + t[:, None] * (p[i + 1] - p[i]), p[-1]]))


def test_portable_scenario_names_the_terrain_by_file(tmp_path):
    """The release's peer gets today's scenario with its built-in terrain named by file: the same seabed."""
    path = portable_scenario("chagos-banks", tmp_path)
    text = path.read_text()
    assert "builtin" not in text and "etopo1_chagos.nc" in text
    a, _ = sc.build(sc.load("chagos-banks"))
    b, _ = sc.build(sc.load(path))
    assert np.array_equal(a.terrain.kernel_data[0], b.terrain.kernel_data[0])
