"""The compiled path cost against an independent computation with the World's own queries."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.cost import CostModel, evaluate_paths, segment_energy
from auvplan.world import Bounds, LambOseenVortices, Margins, Sphere, Terrain, World


def reference_terms(world: World, p: np.ndarray, model: CostModel) -> dict:
    """Every term of :func:`evaluate_paths` from plain numpy and the World's segment queries."""
    a, b = p[:, :-1], p[:, 1:]
    seg = np.stack([a, b], axis=-2)
    d = b - a
    ds = np.linalg.norm(d, axis=-1)
    c = world.currents.velocity(0.5 * (a + b))
    s_hat = d / ds[..., None]
    c_par = (c * s_hat).sum(-1)
    c_perp2 = (c * c).sum(-1) - c_par**2
    root = np.sqrt(np.maximum(model.speed**2 - c_perp2, 0.0))
    blocked = (model.speed**2 < c_perp2) | (c_par + root <= 1e-9)
    dt = ds / np.where(blocked, model.speed, c_par + root)
    joules = (model.hotel_power + model.drag_k * model.speed**3) * dt
    if model.energy == "physical":
        units = joules
    elif model.energy == "document-vehicle":  # eq. 17 with V_oc the vehicle's still-water speed
        units = np.abs(root + c_par) ** 3 * ds / model.speed
    else:
        units = np.abs(root + c_par) ** 3 * ds / np.maximum(np.linalg.norm(c, axis=-1), 1e-3)
    m = world.margins
    alt = world.terrain.segment_min_altitude(seg)  # exact everywhere
    z = seg[..., 2]
    slack = np.minimum.reduce([
        alt - m.min_altitude,
        (-z - m.min_depth).min(-1),
        (m.max_depth + z).min(-1),
        world.bounds.slack(seg).min(-1),
    ])
    clearance = alt.copy()
    for shape in world.obstacles:
        dist = np.minimum(shape.distance(a), shape.distance(b))
        hit = shape.segments_hit(seg, m.obstacle)
        slack = np.minimum(slack, np.where(hit, np.minimum(dist - m.obstacle, -1.0), dist - m.obstacle))
        clearance = np.minimum(clearance, np.where(shape.segments_hit(seg, 0.0), np.minimum(dist, 0.0), dist))
    free = world.segments_free(seg, moving=False)
    assert np.array_equal(free, slack >= 0)  # the reference agrees with the World's own test
    violations = (~free | blocked).sum(-1)
    terrain = model.terrain_penalty * violations + model.violation_slope * np.maximum(-slack, 0).sum(-1)
    energy = model.scale * units.sum(-1)
    return {
        "length": ds.sum(-1),
        "energy_j": joules.sum(-1),
        "duration_s": dt.sum(-1),
        "violations": violations,
        "terrain": terrain,
        "energy": energy,
        "min_clearance": clearance.min(-1),
        "total": model.w_length * ds.sum(-1) + model.w_terrain * terrain + model.w_energy * energy,
    }


@pytest.fixture(scope="module")
def scene(salish):
    """The real Salish shelf with a static sphere, a strong vortex and random wiggly paths near the seabed."""
    _, world, mission = salish
    b = world.bounds
    centre = np.array([0.5 * (b.xmin + b.xmax), 0.5 * (b.ymin + b.ymax)])
    # the vortex peaks at 0.51 m/s, faster than the vehicle: some segments are blocked
    vortex = LambOseenVortices([centre], [4000.0], [800.0])
    seabed = float(world.terrain.elevation(*centre))
    sphere = Sphere((centre[0] + 300.0, centre[1], seabed + 60.0), 80.0)
    w = World(world.bounds, world.terrain, vortex, (sphere,), margins=Margins(min_altitude=10.0, min_depth=5.0,
                                                                              obstacle=5.0))
    rng = np.random.default_rng(11)
    n, s = 40, 120
    t = np.linspace(0.0, 1.0, s)[:, None]
    start = centre + rng.uniform(-1500, 1500, (n, 1, 2))
    end = centre + rng.uniform(-1500, 1500, (n, 1, 2))
    xy = start + t * (end - start) + rng.normal(0.0, 30.0, (n, s, 2))
    z = world.terrain.elevation(xy[..., 0], xy[..., 1]) + rng.uniform(-20.0, 120.0, (n, 1)) \
        + rng.normal(0.0, 8.0, (n, s))
    return w, np.concatenate([xy, z[..., None]], axis=-1)


@pytest.mark.parametrize("energy", ["physical", "document", "document-vehicle"])
def test_compiled_cost_matches_an_independent_computation(scene, energy):
    world, p = scene
    model = CostModel(speed=0.45, energy=energy)
    got = evaluate_paths(world, p, model, exact=True)
    want = reference_terms(world, p, model)
    assert 0 < (want["violations"] > 0).sum() < len(p)  # both feasible and violating paths are present
    assert np.array_equal(got.violations, want["violations"])
    for key in ("length", "energy_j", "duration_s", "terrain", "energy", "min_clearance", "total"):
        assert np.allclose(getattr(got, key), want[key], rtol=1e-9, atol=1e-6), key
    # the fast (bounded) variant changes nothing but clearances far above the threshold
    fast = evaluate_paths(world, p, model)
    assert np.array_equal(fast.violations, got.violations) and np.allclose(fast.total, got.total, rtol=1e-12)
    assert np.all(fast.min_clearance <= got.min_clearance + 1e-9)


def test_segment_energy_broadcasts_and_matches_the_path_cost(scene):
    world, p = scene
    model = CostModel(speed=0.6)
    units, joules, dt, blocked = segment_energy(world, p[:, :-1], p[:, 1:], model)
    terms = evaluate_paths(world, p, model)
    assert np.allclose(joules.sum(-1), terms.energy_j, rtol=1e-12) and np.allclose(dt.sum(-1), terms.duration_s)
    # one origin broadcast against many displacements with a given current
    d = p[0, 1:] - p[0, :-1]
    c = world.currents.velocity(p[0, :-1] + 0.5 * d)
    one = segment_energy(world, np.zeros(3), d, model, current=c)
    assert np.allclose(one[1], joules[0], rtol=1e-12) and np.array_equal(one[3], blocked[0])


def test_open_water_without_a_seabed():
    """A world with no terrain (flow scenes): lengths, still-water energy and the obstacle are analytic."""
    world = World(Bounds(0.0, 1000.0, 0.0, 1000.0, -500.0, 0.0), obstacles=(Sphere((500.0, 500.0, -200.0), 100.0),),
                  margins=Margins(obstacle=10.0))
    x = np.linspace(0.0, 1000.0, 101)
    through = np.c_[x, np.full(101, 500.0), np.full(101, -200.0)]
    beside = np.c_[x, np.full(101, 100.0), np.full(101, -200.0)]
    model = CostModel(speed=1.5)
    terms = evaluate_paths(world, np.stack([through, beside]), model, exact=True)
    assert np.allclose(terms.length, 1000.0) and np.allclose(terms.duration_s, 1000.0 / 1.5)
    assert np.allclose(terms.energy_j, (model.hotel_power + model.drag_k * 1.5**3) * 1000.0 / 1.5)
    # through the sphere: every segment within 110 m of the centre violates (x in [390, 610])
    assert terms.violations[0] == 22 and terms.violations[1] == 0
    assert terms.min_clearance[1] == pytest.approx(300.0) and terms.min_clearance[0] < 0


def test_path_cost_by_hand_at_each_bound_the_depth_limit_and_inside_an_island():
    """Two-point paths whose second point breaks one constraint by a known amount, each one segment
    charged 1e4 + 100 × the amount: 7 m east of the box, 4 m north of it, 3 m south of it, 6 m below
    the 250 m depth limit.  Two 1 m legs 5 m deep inside a flat island 200 m high (the seabed 100 m
    deep around it) are 205 m under the ground: two violations and clearance −205 m with the compiled
    shortcut (``exact=False``) as with the exact walk — the shortcut must take the end altitudes as
    depth minus ground height (on the second leg both ends are carried over from the first)."""
    world = World(Bounds(1000, 2000, -500, 500, -300, 0), margins=Margins(min_depth=5.0, max_depth=250.0))
    paths = np.array([
        [[1900.0, 0.0, -50.0], [2007.0, 0.0, -50.0]],
        [[1500.0, 400.0, -50.0], [1500.0, 504.0, -50.0]],
        [[1500.0, -400.0, -50.0], [1500.0, -503.0, -50.0]],
        [[1500.0, 0.0, -200.0], [1500.0, 0.0, -256.0]],
    ])
    terms = evaluate_paths(world, paths, CostModel())
    np.testing.assert_array_equal(terms.violations, [1, 1, 1, 1])
    np.testing.assert_allclose(terms.terrain, 1e4 + 100.0 * np.array([7.0, 4.0, 3.0, 6.0]))
    x = y = np.linspace(0.0, 2000.0, 41)
    z = np.full((41, 41), -100.0)
    z[15:26, 15:26] = 200.0  # a flat island from 750 to 1250 m
    island = World(Bounds(0, 2000, 0, 2000, -300, 300), terrain=Terrain(x, y, z),
                   margins=Margins(min_altitude=10.0))
    legs = np.array([[[1000.0, 1000.0, -5.0], [1001.0, 1000.0, -5.0], [1002.0, 1000.0, -5.0]]])
    for exact in (False, True):
        t = evaluate_paths(island, legs, CostModel(), exact=exact)
        assert t.violations[0] == 2
        assert t.min_clearance[0] == pytest.approx(-205.0, abs=1e-9)
