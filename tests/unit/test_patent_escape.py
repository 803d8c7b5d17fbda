"""Document 004's local-minimum escape as written (``[avoidance] escape = "patent"``, issue #57).

Steps 3.3.2.5-3.3.2.7 of the patent: while the local-minimum count says trapped, a random obstacle-free
point anywhere in the three-dimensional environment replaces the sub-goal at every new path point; once
the count says free, the first unvisited key waypoint is the sub-goal again.  The oracle of the rule is the
world itself (every draw free and inside the bounds, drawn anew at each path point, dropped when free);
the oracle of the flight is the simulator's exact contact test and the arrival on ``avoidance-net``, where
the issue-#36 rule (``escape = "sampled"``) under the same APF ends in DEADLOCK.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from auvplan._types import Status
from auvplan.guidance.avoidance.local import LocalAvoidance
from auvplan.guidance.avoidance.params import AvoidanceParams
from auvplan.io.scenario import loader as sc
from auvplan.sim import Mission, make_guidance, simulate
from auvplan.world import Bounds, Margins, Sphere, Terrain, World


def _world() -> World:
    """A 600 × 400 m box over a flat seabed at -300 m with a sphere in the way (non-square, both margins)."""
    x, y = np.linspace(-50.0, 650.0, 15), np.linspace(-50.0, 450.0, 11)
    seabed = Terrain(x, y, np.full((y.size, x.size), -300.0))
    return World(Bounds(0, 600, 0, 400, -300, 0), seabed, obstacles=(Sphere((300.0, 200.0, -150.0), 40.0),),
                 margins=Margins(min_altitude=20.0, min_depth=10.0))


def _avoidance(**params: float | str) -> LocalAvoidance:
    w = _world()
    route = np.array([[20.0, 200.0, -150.0], [580.0, 200.0, -150.0]])
    m = Mission("box", tuple(route[0]), tuple(route[1]), route=tuple(map(tuple, route)))
    la = LocalAvoidance(make_guidance("los", route, m), route, w,
                        AvoidanceParams(name="apf", minimum_radius=10.0, minimum_count=5, **params), 1.5, rng=3)
    la.mode = "apf"
    return la


def test_the_rule_in_force_is_each_avoidances_own_unless_chosen():
    assert AvoidanceParams(name="apf").escape_rule == "patent"
    assert AvoidanceParams(name="predictive").escape_rule == "sampled"
    assert AvoidanceParams(name="apf", escape="sampled").escape_rule == "sampled"
    assert AvoidanceParams(name="predictive", escape="patent").escape_rule == "patent"
    with pytest.raises(ValueError, match="escape = 'random'"):
        AvoidanceParams(escape="random")


def test_trapped_draws_a_free_point_anywhere_anew_at_every_path_point_and_drops_it_when_free():
    la = _avoidance()
    p = np.array([100.0, 200.0, -150.0])
    for k in range(4):  # four path points at the same place: not yet trapped (count 5)
        la._patent_escape(p, float(k), la.keys[1])
        assert la.subgoal is None
    draws = []
    for k in range(4, 40):
        g = la._patent_escape(p + [0.0, 0.0, 0.01 * k], float(k), la.keys[1])
        assert la.subgoal is not None and np.array_equal(g, la.subgoal)
        draws.append(la.subgoal.copy())
        # between path points (half a step later) the same sub-goal is kept
        la._patent_escape(p, k + 0.5, la.subgoal)
        assert np.array_equal(la.subgoal, draws[-1])
    d = np.array(draws)
    assert np.all(la.world.is_free(d)) and len({tuple(r) for r in d}) == d.shape[0]  # free, and new every time
    b = la.world.bounds
    # anywhere in the world: the draws spread over the box, far beyond the vehicle's escape_radius
    assert np.ptp(d[:, 0]) > 0.6 * (b.xmax - b.xmin) and np.ptp(d[:, 1]) > 0.6 * (b.ymax - b.ymin)
    assert np.ptp(d[:, 2]) > 0.5 * 250.0 and np.max(np.linalg.norm(d - p, axis=1)) > 3 * la.params.escape_radius
    assert la.escapes == 1 and la.minimum_escapes == 1  # one escape, drawn anew at every path point
    # moved away: the count says free, and the first unvisited key waypoint is the goal again
    g = la._patent_escape(p + [150.0, 0.0, 0.0], 41.0, la.subgoal)
    assert la.subgoal is None and np.array_equal(g, la.keys[la.goal_index])


def test_the_sampled_rule_keeps_its_sub_goal_near_the_vehicle():
    la = _avoidance(escape="sampled")
    p = np.array([100.0, 200.0, -150.0])
    assert la._escape(p, 0.0, minimum=True)
    assert np.linalg.norm(la.subgoal - p) <= la.params.escape_radius * (1 + 1e-9)
    assert abs(la.subgoal[2] - p[2]) <= 0.2 * la.params.escape_radius + 1e-9


@pytest.mark.parametrize("seed", [0, 5])
def test_document_apf_with_the_patents_escape_arrives_on_avoidance_net(seed):
    """avoidance-net under document 004's APF: the patent's escape (drawn in the whole water column, so the
    way over the net's bottom is found) arrives with no contact; issue #36's rule (draws in a thin disc at the
    vehicle's depth) pulls the climbing vehicle back down and round the 240 m wing: DEADLOCK."""
    w, m = sc.build(sc.load("avoidance-net"))
    apf = replace(m, avoidance=replace(m.avoidance, name="apf"))
    r = simulate(w, apf, rng=seed)
    assert r.status is Status.EXACT and r.metrics["collisions"] == 0 and r.obstacle_distance.min() > 0.0
    assert r.minimum_escapes >= 1
    if seed == 0:  # the sampled rule's draws undo the climb over the net (not every seed: 5 arrives)
        sampled = simulate(w, replace(apf, avoidance=replace(apf.avoidance, escape="sampled")), rng=seed)
        assert sampled.status is Status.DEADLOCK and sampled.metrics["collisions"] == 0
