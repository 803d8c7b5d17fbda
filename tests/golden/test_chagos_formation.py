"""The shipped ``chagos-formation`` scenario: its formation plan on the default (conservative) seabed.

The plan step only (the closed-loop flight takes ~10 s more): feasible, line → column through the
channel saddle → line → wedge, with two oracles measured on the terrain independently of the planner's
exact segment test: every slot track sampled every 2 m keeps the minimum altitude, and the corridor
across the route at the saddle crest (seabed deeper than survey depth + minimum altitude) is too
narrow on one side for the 1.2 km line but holds every slot of the column.
"""

from __future__ import annotations

import numpy as np
import pytest

from auvplan._types import Status
from auvplan.guidance.formation.plan import FormationPlan, plan_formation
from auvplan.io.scenario import loader as sc
from auvplan.sim.mission import Mission
from auvplan.sim.pipeline import planned_route
from auvplan.world import World

Built = tuple[str, World, Mission, FormationPlan]


@pytest.fixture(scope="module")
def chagos() -> Built:
    scenario = sc.load("chagos-formation")
    world, mission = sc.build(scenario)
    assert mission.formation is not None
    _, route = planned_route(world, mission, mission.seed)
    assert route is not None
    return scenario.description, world, mission, plan_formation(world, route, mission.formation)


def _crest(world: World, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """The shallowest seabed point on the leg a→b (1 m steps), the leg's unit direction and left normal."""
    u = (b - a) / np.linalg.norm(b - a)
    t = np.arange(0.0, float(np.linalg.norm(b - a)), 1.0)
    p = a + t[:, None] * u
    z = world.seabed(p[:, 0], p[:, 1])
    k = int(np.argmax(z))
    return p[k], u, np.array([-u[1], u[0]]), float(t[k])


def _corridor(world: World, c: np.ndarray, n: np.ndarray, level: float) -> tuple[float, float]:
    """Right and left edges (m along ``n`` from ``c``) of the stretch through ``c`` with seabed ≤ level."""
    off = np.arange(-3000.0, 3000.5, 1.0)
    ok = world.seabed(c[0] + off * n[0], c[1] + off * n[1]) <= level
    i = off.size // 2
    assert ok[i]
    lo, hi = i, i
    while lo > 0 and ok[lo - 1]:
        lo -= 1
    while hi < off.size - 1 and ok[hi + 1]:
        hi += 1
    return float(off[lo]), float(off[hi])


def test_chagos_formation_plan_column_through_saddle(chagos: Built) -> None:
    description, world, m, fplan = chagos
    assert m.formation is not None
    fp = m.formation.params
    route = np.asarray(m.route, dtype=float)
    depth = -route[0, 2]
    min_alt = world.margins.min_altitude
    assert np.all(route[:, 2] == -depth) and min_alt == 50.0
    assert f"{depth:.0f} m deep" in description  # the description states the true survey depth

    # feasible, and the shapes the description promises
    assert fplan.status is Status.EXACT, fplan.message
    assert [sh for _, sh in fplan.breaks] == ["line", "column", "line", "wedge"]
    (c0, _), (c1, _) = fplan.breaks[1], fplan.breaks[2]

    # the saddle crest on the route (leg 0→1) lies inside the column stretch, with the whole column
    # ((n - 1) spacings behind the leader) past it before the line re-forms
    crest, u, n, along = _crest(world, route[0, :2], route[1, :2])
    tail = (len(m.formation.vehicles) - 1) * fp.spacing_m
    assert c0 + fp.transition_m <= along and along + tail <= c1

    # oracle 1: every slot track, sampled every 2 m, keeps the minimum altitude above the seabed
    tracks = fplan.tracks
    k = int(np.ceil(np.linalg.norm(np.diff(tracks[..., :2], axis=1), axis=-1).max() / 2.0))
    f = np.arange(k) / k
    dense = (tracks[:, :-1, None, :] * (1 - f)[None, None, :, None]
             + tracks[:, 1:, None, :] * f[None, None, :, None]).reshape(tracks.shape[0], -1, 3)
    assert np.linalg.norm(np.diff(dense[..., :2], axis=1), axis=-1).max() <= 2.0 + 1e-9
    alt = dense[..., 2] - world.seabed(dense[..., 0], dense[..., 1])
    assert alt.min() >= min_alt

    # oracle 2: the corridor across the route at the crest, measured on the terrain
    right, left = _corridor(world, crest, n, -depth - min_alt)
    assert right > -fp.spacing_m or left < fp.spacing_m  # the line's outer slots do not fit: reshape needed
    rel = tracks[..., :2] - crest
    near = np.abs(rel @ u) <= 150.0  # slot positions abeam of the crest
    for v in range(tracks.shape[0]):
        assert near[v].any()
        lat = rel[v][near[v]] @ n
        assert right < lat.min() and lat.max() < left  # the column's width fits the corridor
