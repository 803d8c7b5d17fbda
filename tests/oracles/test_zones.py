"""Charted no-go zones (issue 53): the exact segment-vs-prism test against an independent shapely check,
distances, the readers of every vector format, the planners' final word, ``mission check``."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import shapely
from benchmarks.zones import free_point, independent_entries, random_world, spec_for

from auvplan.cli import main
from auvplan.cost import CostModel, evaluate_paths
from auvplan.errors import ScenarioError
from auvplan.io.scenario.build import build
from auvplan.io.scenario.loader import loads
from auvplan.planners import PlannerSpec, PlanningProblem, plan, register
from auvplan.planners.core.registry import REGISTRY
from auvplan.world import Zone, Zones
from helpers import flat_world


# ---------------------------------------------------------------------- the exact test
@pytest.mark.parametrize("seed", [0, 1])
def test_entries_match_an_independent_shapely_check(seed):
    rng = np.random.default_rng(seed)
    world = random_world(rng, 12)
    zones = world.zones.exact
    p = np.column_stack([rng.uniform(0, 3000, 400), rng.uniform(0, 3000, 400), rng.uniform(-250, -5, 400)])
    p[50:60, :2] = p[50, :2]  # vertical legs
    p[100:110, 2] = p[100, 2]  # level legs
    seg, zi = zones.entries(np.stack([p[:-1], p[1:]], axis=1))
    ours = {(int(s) + 1, zones.names[int(z)]) for s, z in zip(seg, zi)}
    theirs = set(independent_entries(world, p))
    assert len(theirs) > 20
    assert ours == theirs
    # the planners' compiled pass (fine-field cull, march, discs, early exit) on long legs and on a short-step walk
    walk = np.cumsum(np.column_stack([rng.normal(0, 40, (2000, 2)), rng.normal(0, 4, 2000)]), axis=0)
    walk += [1500.0, 1500.0, -120.0] - walk.mean(axis=0)
    for path in (p, walk):
        legs = {k for k, _ in independent_entries(world, path)}
        assert set(np.flatnonzero(zones.segments_enter(np.stack([path[:-1], path[1:]], axis=1))) + 1) == legs
        assert set(np.flatnonzero(zones.polyline_inside_lengths(path[None])[0] > 0) + 1) == legs
    assert len(legs) > 20


def test_signed_distance_is_the_prism_distance_and_never_above_it():
    z = Zones((Zone("box", shapely.box(0, 0, 100, 100), top=20.0, bottom=50.0),))
    d = z.signed_distance(np.array([[150.0, 50.0, -10.0], [50.0, 50.0, -30.0], [50.0, 130.0, -35.0]]), exact=True)
    np.testing.assert_allclose(d, [math.hypot(50.0, 10.0), -10.0, 30.0])
    rng = np.random.default_rng(3)
    world = random_world(rng, 40)
    pts = np.column_stack([rng.uniform(-500, 3500, (3000, 2)), rng.uniform(-300, 0, 3000)])
    fast, exact = world.zones.signed_distance(pts), world.zones.signed_distance(pts, exact=True)
    assert np.all(fast <= exact + 1e-9)
    near = exact < 2.0 * world.zones._grid[2]
    np.testing.assert_allclose(fast[near], exact[near])


def test_the_pad_keeps_planners_off_and_checks_test_the_zone_itself():
    zones = Zones((Zone("wreck", shapely.box(0, 0, 10, 10)),), pad=1.0)
    leg = np.array([[[-5.0, 10.5, -5.0], [20.0, 10.5, -5.0]]])  # 0.5 m north of the footprint
    assert zones.segments_enter(leg)[0] and not zones.exact.segments_enter(leg)[0]


def test_a_seabed_band_follows_the_seabed():
    world = flat_world(depth=100.0)
    zones = Zones((Zone("pipeline", shapely.box(400, 0, 600, 1000), above_seabed=15.0),), world.terrain)
    over = np.array([[[0.0, 500.0, -84.0], [1000.0, 500.0, -84.0]], [[0.0, 500.0, -86.0], [1000.0, 500.0, -86.0]]])
    assert zones.segments_enter(over).tolist() == [False, True]  # 16 m and 14 m above the seabed


# ---------------------------------------------------------------------- readers
ORIGIN = (-7.0, 70.8)
SQUARE = [(-6.95, 70.85), (-6.95, 70.9), (-6.9, 70.9), (-6.9, 70.85)]  # [lat, lon] corners


def _scenario(zones_toml: str, base: Path | None = None) -> tuple:
    text = f"""
[origin]
lat = {ORIGIN[0]}
lon = {ORIGIN[1]}
[bounds]
x = [0.0, 20000.0]
y = [0.0, 20000.0]
z = [-500.0, 0.0]
[terrain.synthetic]
kind = "flat"
depth = 400.0
[mission]
start = [1000.0, 1000.0, -100.0]
goal = [19000.0, 19000.0, -100.0]
min_altitude_m = 20.0
{zones_toml}
"""
    return build(loads(text, source="test.toml", base_dir=base))


def _write(path: Path, driver: str, crs: str, geoms: list, names: list[str], layer: str | None = None) -> None:
    import pyogrio

    pyogrio.raw.write(path, np.array(shapely.to_wkb(geoms), dtype=object), [np.array(names, dtype=object)],
                      ["name"], driver=driver, crs=crs, geometry_type=geoms[0].geom_type, layer=layer)


@pytest.mark.parametrize(("suffix", "driver", "crs"), [("geojson", "GeoJSON", "EPSG:4326"), ("kml", "KML", "EPSG:4326"),
                                                       ("shp", "ESRI Shapefile", "EPSG:32743"),
                                                       ("gpkg", "GPKG", "EPSG:3857")])
def test_every_vector_format_reads_to_the_same_footprint(tmp_path, suffix, driver, crs):
    from pyproj import Transformer

    inline, _ = _scenario("[[zones]]\nname = 'area'\npolygon = " + str([list(c) for c in SQUARE]))
    ll = Transformer.from_crs("EPSG:4326", crs, always_xy=True)
    ring = [ll.transform(lon, lat) for lat, lon in SQUARE]
    other = shapely.Polygon([(x + 30000.0, y) for x, y in ring]) if crs != "EPSG:4326" else \
        shapely.Polygon([(x + 0.3, y) for x, y in ring])
    _write(tmp_path / f"zones.{suffix}", driver, crs, [shapely.Polygon(ring), other], ["keep", "drop"],
           layer="areas" if suffix == "gpkg" else None)
    extra = 'layer = "areas"\n' if suffix == "gpkg" else ""
    world, _ = _scenario(f"[[zones]]\nname = 'file'\nfile = 'zones.{suffix}'\n{extra}where = \"name = 'keep'\"\n",
                         tmp_path)
    assert world.zones.names == ["file: keep"]
    a, b = inline.zones.exact.zones[0].footprint, world.zones.exact.zones[0].footprint
    assert shapely.area(shapely.symmetric_difference(a, b)) < 2e-3 * shapely.area(a)


def test_lines_and_points_are_buffered_and_metres_are_metres():
    world, _ = _scenario("""
[[zones]]
name = "cable"
line = [[5000.0, 0.0], [5000.0, 20000.0]]
buffer_m = 50.0
top_m = 10.0
bottom_m = 200.0
[[zones]]
name = "wreck"
point = [-6.95, 70.95]
radius_m = 300.0
above_seabed_m = 20.0
""")
    cable, wreck = world.zones.exact.zones
    assert cable.footprint.bounds == pytest.approx((4950.0, -50.0, 5050.0, 20050.0), rel=2e-3)
    assert shapely.contains(cable.footprint, shapely.buffer(shapely.LineString([(5000, 0), (5000, 20000)]), 49.99,
                                                            quad_segs=64))
    assert (cable.top, cable.bottom) == (10.0, 200.0)
    assert math.pi * 300.0**2 < shapely.area(wreck.footprint) < 1.003 * math.pi * 300.0**2  # contains the circle
    assert wreck.above_seabed == 20.0


@pytest.mark.parametrize(("table", "words"), [
    ("name = 'a'\npolygon = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]\nline = [[0.0, 0.0], [1.0, 1.0]]", "exactly one of"),
    ("name = 'a'\nline = [[0.0, 0.0], [1.0, 1.0]]", "needs buffer_m"),
    ("name = 'a'\npoint = [0.0, 0.0]\nradius_m = -1.0", "radius_m = -1.0"),
    ("name = 'a'\npoint = [0.0, 0.0]\nradius_m = 5.0\ntop_m = 50.0\nbottom_m = 20.0", "bottom_m = 20"),
    ("name = 'a'\npoint = [0.0, 0.0]\nradius_m = 5.0\ncolour = 'red'", "unknown key 'colour'"),
    ("name = 'a'\npolygon = [[0.0, 0.0], [1.0]]", "polygon = "),
    ("name = 'a'\nfile = 'missing.gpkg'", "not found"),
])
def test_bad_zone_tables_name_the_file_key_and_value(table, words):
    with pytest.raises(Exception) as err:
        _scenario("[[zones]]\n" + table)
    assert "test.toml" in str(err.value) and words in str(err.value)


# ---------------------------------------------------------------------- planners
@pytest.mark.parametrize("planner", ["iabc", "grid", "timeopt"])
def test_plans_reported_feasible_never_enter_a_zone(planner):
    rng = np.random.default_rng(11)
    feasible = 0
    for m in range(4):
        world = random_world(rng, 10)
        problem = PlanningProblem(world, free_point(rng, world), free_point(rng, world), speed=1.5)
        result = plan(problem, spec_for(planner), rng=m)
        if result.status.ok:
            feasible += 1
            assert independent_entries(world, result.path) == []
            assert result.cost_terms["zone_clearance_min_m"] > 0.0
    assert feasible >= 3


def test_a_planner_that_cannot_honour_zones_is_refused():
    world = random_world(np.random.default_rng(2), 3)
    problem = PlanningProblem(world, np.array([100.0, 100.0, -20.0]), np.array([2900.0, 2900.0, -20.0]))
    with pytest.raises(ScenarioError, match="planner 'flow' cannot keep out"):
        plan(problem, PlannerSpec(name="flow"))


def test_a_plan_through_a_zone_is_never_feasible_and_names_zone_and_leg():
    from auvplan._types import Status
    from auvplan.planners.core.base import PlanResult
    from auvplan.planners.core.common import plan_terms

    @register("straight_zoned", iterative=False, description="a straight line (test)", capabilities=("zones",))
    def straight(problem, spec, rng=None, progress=None):
        path = np.array([problem.start, 0.5 * (problem.start + problem.goal), problem.goal])
        return PlanResult(Status.EXACT, path, 1.0, {}, 1, 1, 0.0, np.zeros(1), "straight_zoned")

    try:
        world = flat_world()
        world = type(world)(**{**world.__dict__, "zones": Zones((Zone("wreck", shapely.box(700, 700, 800, 800)),),
                                                                 world.terrain)})
        problem = PlanningProblem(world, np.array([100.0, 100.0, -50.0]), np.array([900.0, 900.0, -50.0]))
        result = plan(problem, PlannerSpec(name="straight_zoned"))
        assert result.status == Status.INFEASIBLE
        assert "leg 2 enters zone 'wreck'" in result.message
        assert result.cost_terms["zone_clearance_min_m"] <= 0.0
    finally:
        del REGISTRY["straight_zoned"]
    del plan_terms


def test_the_cost_counts_a_segment_through_a_zone():
    world = flat_world()
    model = CostModel(speed=1.5)
    path = np.array([[100.0, 500.0, -50.0], [900.0, 500.0, -50.0]])
    assert evaluate_paths(world, path, model).violations[0] == 0
    zoned = type(world)(**{**world.__dict__, "zones": Zones((Zone("area", shapely.box(400, 400, 600, 600),
                                                                  top=40.0, bottom=60.0),), world.terrain)})
    terms = evaluate_paths(zoned, path, model)
    assert terms.violations[0] == 1  # as deep as the leg: M per segment plus the slope per metre of its 800 m
    assert terms.terrain[0] == pytest.approx(model.terrain_penalty + model.violation_slope * 800.0, rel=1e-9)
    assert evaluate_paths(zoned, path + [0.0, 0.0, -15.0], model).violations[0] == 0  # 65 m deep: below the band


# ---------------------------------------------------------------------- mission check on the built-in
def test_mission_check_fails_a_planted_mission_naming_the_zone_and_the_leg(tmp_path, capsys):
    planted = tmp_path / "planted.csv"
    planted.write_text("x,y,z\n140000,180000,-100\n150000,182000,-100\n170000,186000,-100\n190000,190000,-100\n")
    assert main(["mission", "check", str(planted), "--scenario", "chagos-reefs"]) == 1
    out = capsys.readouterr().out
    assert "zone 'reef: Salomon Islands': FAIL — entered by leg 1" in out  # leaving waypoint 1 (from 0)
    assert "zone 'reef: Blenheim Reef': OK — closest approach" in out


def test_lattice_edges_the_seabed_clears_still_keep_out_of_zones():
    """The lattice's free edges (``grid``, ``--reference``, ``timeopt``): none enters a zone (oracle: the
    independent shapely check), though most are cleared by the node values without the full segment test."""
    from auvplan.planners.grid.lattice import HALF, edge_states, node_fields

    world = random_world(np.random.default_rng(5), 15)
    axes = (np.linspace(50.0, 2950.0, 25), np.linspace(50.0, 2950.0, 23), np.linspace(-280.0, -10.0, 6))
    free, alt, obs, _ = node_fields(world, axes, False)
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    steps = np.array([axes[0][1] - axes[0][0], axes[1][1] - axes[1][0], axes[2][1] - axes[2][0]])
    near = shapely.union_all([z.footprint for z in world.zones.exact.zones])
    rng = np.random.default_rng(0)
    kept = 0
    for off in HALF[:6]:
        state = edge_states(world, free, alt, obs, steps, off, grid.__getitem__)
        src = np.flatnonzero(state == 1)
        dst = src + int((off[0] * free.shape[1] + off[1]) * free.shape[2] + off[2])
        mid = 0.5 * (grid[src] + grid[dst])
        close = np.flatnonzero(shapely.distance(near, shapely.points(mid[:, :2])) < 0.6 * steps[0])
        for i in rng.choice(close, min(close.size, 60), replace=False):  # the edges that skirt a zone
            assert independent_entries(world, np.stack([grid[src[i]], grid[dst[i]]])) == []
        kept += close.size
    assert kept > 300


@pytest.mark.parametrize("cells, stretch", [(None, 1.0), (2e3, 1.0), (3e4, 3.0)])
def test_the_fine_field_never_exceeds_the_distance_to_a_footprint_and_is_tight_near_them(cells, stretch):
    """The planners' fine lower-bound field against shapely's distance (the independent oracle): never above
    it anywhere (else a leg near a zone would pass unchecked), within 1.5 fine cells of it near the zones;
    with the default size, with one fine cell per broad-phase cell (a set of a thousand zones gets few per
    cell), and on footprints stretched three times along x (a grid twice as wide as it is tall)."""
    from auvplan.world.zones.bound import _far
    from auvplan.world.zones.parts import distance_field

    rng = np.random.default_rng(5)
    world = random_world(rng, 30)
    zones = world.zones
    if stretch != 1.0:
        stretched = [replace(z, footprint=shapely.affinity.scale(z.footprint, stretch, 1.0, origin=(0, 0)))
                     for z in zones.zones if z.above_seabed is None]
        zones = Zones(tuple(stretched), pad=zones.pad)
        assert zones._grid[3] >= 2 * zones._grid[4]  # twice as many columns as rows
    field = zones._field if cells is None else distance_field(zones._grid, zones._rings, zones._bounds, cells=cells)
    x0, y0, f, fnx, fny, bound = field[:6]
    every = bound.shape[0] - 1  # the plane of every zone
    if cells is not None:
        assert fnx % zones._grid[3] == 0 and fnx < 16 * zones._grid[3] and (cells > 1e4 or fnx == zones._grid[3])
    pts = np.column_stack([rng.uniform(-400, 3000 * stretch + 400, 8000), rng.uniform(-400, 3400, 8000)])
    lb = np.array([_far.py_func(x, y, every, every, x0, y0, f, fnx, fny, bound) for x, y in pts])
    true = shapely.distance(shapely.union_all(zones._geoms), shapely.points(pts))
    assert np.all(lb <= true)
    inside = (pts[:, 0] > x0) & (pts[:, 0] < x0 + fnx * f) & (pts[:, 1] > y0) & (pts[:, 1] < y0 + fny * f)
    near = (true > 0) & (true < 4 * f) & inside  # outside the field's rectangle: the distance to the rectangle
    assert near.sum() > 400 and np.all(lb[near] >= true[near] - 1.5 * f)


def test_segments_sharing_traces_enter_exactly_where_each_alone_does():
    """``Zones.traces_enter`` (the lattice's per-column test: 2D once per trace, bands per edge) against the
    exact segment test and the independent shapely check, with level, sloping and vertical segments."""
    rng = np.random.default_rng(11)
    world = random_world(rng, 25)
    zones = world.zones
    a = rng.uniform(0, 3000, (300, 2))
    traces = np.stack([a, a + rng.normal(0, 600, (300, 2))], axis=1)
    traces[:20, 1] = traces[:20, 0]  # vertical segments: a point trace
    of = rng.integers(0, 300, 4000)
    za = rng.uniform(-300, 0, 4000)
    zb = za + rng.normal(0, 40, 4000)
    zb[:400] = za[:400]
    seg = np.zeros((4000, 2, 3))
    seg[:, :, :2] = traces[of]
    seg[:, 0, 2], seg[:, 1, 2] = za, zb
    got = zones.traces_enter(traces, of, za, zb)
    np.testing.assert_array_equal(got, zones.segments_enter(seg))
    exact = world.zones.exact
    got = exact.traces_enter(traces, of, za, zb)
    theirs = np.array([bool(independent_entries(world, s)) for s in seg[::10]])
    assert theirs.sum() > 50
    np.testing.assert_array_equal(got[::10], theirs)


def test_legs_grazing_corners_and_band_faces_enter_exactly_where_shapely_says():
    """The compiled passes (cell pass-by test, fine-field march, discs, edges) on legs that only touch a prism:
    through a footprint's corner from outside, along an edge, level on a band's top or bottom face, ending on
    a face, and a hair (1e-9 m) off each; the closed prism counts touching as entering."""
    box = Zone("box", shapely.box(100.0, 100.0, 300.0, 200.0), top=20.0, bottom=60.0)
    tri = Zone("tri", shapely.Polygon([(500.0, 100.0), (700.0, 100.0), (600.0, 300.0)]))
    world = replace(flat_world(depth=100.0), zones=Zones((box, tri)))
    legs = []
    for (cx, cy), (dx, dy) in (((100, 100), (1, -1)), ((300, 100), (1, 1)), ((300, 200), (-1, 1)),
                               ((100, 200), (1, 1)), ((500, 100), (1, 1)), ((700, 100), (-1, 1))):
        for z in (-20.0, -40.0, -60.0, -19.0, -61.0):  # top face, inside, bottom face, above, below the band
            legs.append([[cx - 50 * dx, cy - 50 * dy, z], [cx + 50 * dx, cy + 50 * dy, z]])
            legs.append([[cx - 50 * dx, cy - 50 * dy + 1e-9, z], [cx + 50 * dx, cy + 50 * dy + 1e-9, z]])
    for z0, z1 in ((-10.0, -20.0), (-70.0, -60.0), (-10.0, -20.0 + 1e-9), (-70.0, -60.0 - 1e-9)):
        legs.append([[200.0, 150.0 + 60.0, z0], [200.0, 150.0, z1]])  # ending on the top / bottom face
        legs.append([[50.0, 200.0, z0], [350.0, 200.0, z1]])  # along the north edge
        legs.append([[50.0, 200.0 + 1e-9, z1], [350.0, 200.0 + 1e-9, z1]])
    seg = np.array(legs)
    theirs = np.array([bool(independent_entries(world, s)) for s in seg])
    assert 20 < theirs.sum() < len(seg) - 20
    zones = world.zones
    np.testing.assert_array_equal(zones.segments_enter(seg), theirs)
    np.testing.assert_array_equal(np.isin(np.arange(len(seg)), zones.entries(seg)[0]), theirs)
    np.testing.assert_array_equal(zones.polyline_slack(seg)[:, 0] < 0, theirs)


def test_the_unpadded_set_a_padded_one_derives_answers_as_one_built_alone():
    """``Zones.exact`` shares the padded set's cell lists and fine field: every query answers as a set built
    from the footprints alone (and the entries as the independent shapely check)."""
    rng = np.random.default_rng(21)
    world = random_world(rng, 30)
    derived, alone = world.zones.exact, Zones(world.zones.zones, world.terrain)
    assert derived._field is world.zones._field
    p = np.column_stack([rng.uniform(0, 3000, 200), rng.uniform(0, 3000, 200), rng.uniform(-250, -5, 200)])
    # and level legs across each flat band's footprint half a metre above its top / below its bottom (inside
    # the padded prism only) and on the face
    flat = [z for z in world.zones.zones if z.above_seabed is None and z.top > 1.0 and math.isfinite(z.bottom)]
    for z in flat:
        c = shapely.get_coordinates(shapely.centroid(z.footprint))[0]
        for depth in (z.top - 0.5, z.top, z.bottom, z.bottom + 0.5):
            p = np.vstack([p, [c[0] - 900.0, c[1], -depth], [c[0] + 900.0, c[1], -depth]])
    seg = np.stack([p[:-1], p[1:]], axis=1)
    a, b = derived.entries(seg), alone.entries(seg)
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])
    assert {(int(s) + 1, derived.names[int(z)]) for s, z in zip(*a)} == set(independent_entries(world, p))
    np.testing.assert_array_equal(derived.segments_enter(seg), alone.segments_enter(seg))
    np.testing.assert_array_equal(derived.polyline_slack(p[None]), alone.polyline_slack(p[None]))
    np.testing.assert_array_equal(derived.signed_distance(p, exact=True), alone.signed_distance(p, exact=True))
    near = alone.signed_distance(p) < 2.0 * alone._grid[2]
    np.testing.assert_array_equal(derived.signed_distance(p)[near], alone.signed_distance(p)[near])
    assert derived.clearance(p) == alone.clearance(p)
    tail = p[-30:]  # the level legs across the bands
    assert [z.as_dict() for z in derived.approach(tail)] == [z.as_dict() for z in alone.approach(tail)]


def test_views_of_a_set_keep_its_class_and_answer_as_sets_built_alone():
    """``with_pad`` and ``exact`` (built in :mod:`auvplan.world.zones.index`, below the queries) are the
    full :class:`Zones`: every query of the package answers, as a set built alone with that pad does."""
    rng = np.random.default_rng(5)
    world = random_world(rng, 12)
    zones = world.zones
    assert zones.with_pad(zones.pad) is zones and zones.exact.exact is zones.exact
    grown, alone = zones.with_pad(6.0), Zones(zones.zones, world.terrain, pad=6.0)
    assert type(grown) is Zones and type(zones.exact) is Zones and grown.pad == 6.0
    p = np.column_stack([rng.uniform(0, 3000, 120), rng.uniform(0, 3000, 120), rng.uniform(-250, -5, 120)])
    a, b = p[:-1], p[1:]
    got, want = grown.envelopes_enter(a, b), alone.envelopes_enter(a, b)
    assert 5 < want.sum() < len(a) - 5
    np.testing.assert_array_equal(got, want)
    np.testing.assert_array_equal(grown.polyline_slack(p[None]), alone.polyline_slack(p[None]))
    np.testing.assert_array_equal(grown.signed_distance(p, exact=True), alone.signed_distance(p, exact=True))


@pytest.mark.parametrize("pad", [0.05, 0.6])
def test_a_smaller_pad_derived_from_a_set_answers_as_a_set_built_alone(pad, monkeypatch):
    """``with_pad`` below the set's pad (the mission builder's 5 cm) shares the set's cell lists and fine field
    and answers as a set built alone with that pad: entries (level legs a centimetre either side of the grown
    bands' faces), the compiled passes, exact distances, distances near the zones; kept per pad.  When a
    grown footprint were not inside the set's, it is built alone."""
    rng = np.random.default_rng(8)
    world = random_world(rng, 16)
    zones = world.zones
    derived, alone = zones.with_pad(pad), Zones(zones.zones, world.terrain, pad=pad)
    assert derived._field is zones._field and zones.with_pad(pad) is derived and derived.pad == pad
    for k in (8, 9):  # the broad phase's bands (bottoms, tops: a seabed band's over the highest seabed) its own
        np.testing.assert_array_equal(derived._grid[k], alone._grid[k])
    p = np.column_stack([rng.uniform(0, 3000, 160), rng.uniform(0, 3000, 160), rng.uniform(-250, -5, 160)])
    for z in zones.zones:  # level legs across flat bands just inside / outside the grown band's faces
        if z.above_seabed is None and z.top > 1.0 and math.isfinite(z.bottom):
            c = shapely.get_coordinates(shapely.centroid(z.footprint))[0]
            for depth in (z.top - pad - 0.01, z.top - pad + 0.01, z.bottom + pad - 0.01, z.bottom + pad + 0.01):
                p = np.vstack([p, [c[0] - 900.0, c[1], -depth], [c[0] + 900.0, c[1], -depth]])
    t = world.terrain
    gx, gy = np.meshgrid(t.x, t.y)
    tops = 0
    for z in zones.zones:  # and a centimetre under a grown seabed band's top over the highest node in its box
        if z.above_seabed is not None:
            box = shapely.buffer(z.footprint, pad, join_style="mitre")
            x0, y0, x1, y1 = shapely.bounds(box)
            inbox = (gx >= x0) & (gx <= x1) & (gy >= y0) & (gy <= y1)
            if inbox.any():
                k = np.flatnonzero(inbox.ravel())[np.argmax(np.asarray(t.z).ravel()[inbox.ravel()])]
                x, y, zt = gx.ravel()[k], gy.ravel()[k], np.asarray(t.z).ravel()[k]
                if shapely.contains_xy(box, x, y):
                    level = zt + z.above_seabed + pad - 0.01
                    p = np.vstack([p, [x - 5.0, y, level], [x + 5.0, y, level]])
                    tops += 1
    assert tops >= 2
    seg = np.stack([p[:-1], p[1:]], axis=1)
    a, b = derived.entries(seg), alone.entries(seg)
    assert 10 < a[0].size and np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
    np.testing.assert_array_equal(derived.segments_enter(seg), alone.segments_enter(seg))
    np.testing.assert_array_equal(derived.envelopes_enter(p[:-1], p[1:]), alone.envelopes_enter(p[:-1], p[1:]))
    np.testing.assert_array_equal(derived.polyline_slack(p[None]), alone.polyline_slack(p[None]))
    np.testing.assert_array_equal(derived.signed_distance(p, exact=True), alone.signed_distance(p, exact=True))
    near = alone.signed_distance(p) < 2.0 * alone._grid[2]
    np.testing.assert_array_equal(derived.signed_distance(p)[near], alone.signed_distance(p)[near])
    monkeypatch.setattr(shapely, "covers", lambda a, b: np.zeros(np.broadcast(a, b).shape, dtype=bool))
    rebuilt = Zones(zones.zones, world.terrain, pad=1.0).with_pad(pad)
    assert rebuilt._field is not zones._field and np.array_equal(rebuilt.entries(seg)[0], b[0])
