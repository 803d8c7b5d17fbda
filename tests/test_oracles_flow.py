"""Oracle tests of document 000's flow planner: the field's parts and the streamlines' stop rules.

The survivors of the mutation run on ``flow`` (docs/mutants.md §2) each met one of these: a small
independent computation (an image by hand, an analytic speed, a rule's threshold read off the path)
that a one-line bug in ``planners/flow.py`` or ``planners/flow_stream.py`` breaks.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from auvplan.planners.flow import FlowField, FlowParams, integrate_streamlines, sink_velocity
from auvplan.planners.flow_stream import MAX_CORRECTIONS
from auvplan.world import Ellipsoid, Sphere

GOAL = np.array([30.0, 0.0, 0.0])
ELLIPSOID = Ellipsoid((0.0, 0.0, 0.0), (8.0, 4.0, 3.0))


# ---------------------------------------------------------------------- the field
def test_mirror_sink_is_the_image_of_the_target_in_the_plane():
    """A plane at z = −50 m and the target T = (12, −7, −42) (m = 2): the field is the sink plus a sink
    of the same strength at T's mirror image (12, −7, −58), by hand, and no flow crosses the plane."""
    target = np.array([12.0, -7.0, -42.0])
    field = FlowField((), target, FlowParams(strength=2.0), plane=-50.0)
    rng = np.random.default_rng(11)
    p = rng.uniform(-40.0, 40.0, (50, 3)) + (0.0, 0.0, -20.0)
    p[:, 2] = np.abs(p[:, 2] + 50.0) - 50.0  # above the plane
    expected = sink_velocity(p, target, 2.0) + sink_velocity(p, [12.0, -7.0, -58.0], 2.0)
    np.testing.assert_allclose(field.velocity(p), expected, rtol=1e-12)
    on_plane = np.column_stack([p[:, :2], np.full(len(p), -50.0)])
    u = field.velocity(on_plane)
    assert np.abs(u[:, 2]).max() <= 1e-12 * np.linalg.norm(u, axis=1).max()


def test_push_out_from_just_inside_a_line_distribution_body_lands_on_its_surface():
    """Points δ = 10⁻³ R inside the flow body of the (8, 4, 3) ellipsoid, built by hand from its meridian
    profile (the middle of a segment, moved in along the segment's left-hand normal, turned about the
    axis): ``push_out`` moves each back out along that normal by δ + eps·R (eps = 10⁻⁶), onto the profile
    to within 2·10⁻⁶ R (the graze correction's move); the body's own ``normal`` there is the same outward
    unit vector (it was the inward one: the correction pushed grazing points deeper in)."""
    field = FlowField((ELLIPSOID,), GOAL, FlowParams(), 0.5)
    body = field.bodies[0]
    radius = float(field.radii[0])
    prof = body.profile
    j = np.arange(5, prof.shape[0] - 6, 7)
    mid, t = 0.5 * (prof[j] + prof[j + 1]), prof[j + 1] - prof[j]
    n2 = np.column_stack([-t[:, 1], t[:, 0]]) / np.linalg.norm(t, axis=1)[:, None]  # (x, ρ): outward
    phi = np.linspace(0.0, 2.0 * math.pi, j.size, endpoint=False)
    turn = np.column_stack([np.zeros(j.size), np.cos(phi), np.sin(phi)])
    outward = (np.column_stack([n2[:, 0], np.zeros(j.size), np.zeros(j.size)]) + n2[:, 1:2] * turn) @ body.basis.T
    delta = 1e-3 * radius
    inner = mid - delta * n2
    points = body.center + (np.column_stack([inner[:, 0], np.zeros(j.size), np.zeros(j.size)])
                            + inner[:, 1:2] * turn) @ body.basis.T
    assert (field.distances(points, "true")[:, 0] < -0.9 * delta).all()
    np.testing.assert_allclose(body.normal(points), outward, atol=1e-12)
    moved = field.push_out(points, 1e-6)
    np.testing.assert_allclose(moved - points, (delta + 1e-6 * radius) * outward, rtol=0, atol=1e-3 * delta)
    assert (np.abs(body.distance(moved)) <= 2e-6 * radius).all()  # on the profile polyline (to eps)


def test_exit_rule_leaves_a_body_straight_along_its_normal_where_that_lands_outside():
    """Starts 10⁻³ R inside the flow body of the (8, 4, 3) ellipsoid, built by hand from its meridian profile
    (a tenth, half and nine tenths along a segment, in along the segment's left-hand normal n, turned about
    the axis): where the straight move to p + (depth + 10⁻⁶ R) n lands outside the body, clear of the
    obstacle, that is the exit rule's point (by hand, n independent of the body's own ``normal``)."""
    from auvplan.planners.flow_stream import _exit_body, _segment_clear

    field = FlowField((ELLIPSOID,), GOAL, FlowParams(), 0.5)
    body = field.bodies[0]
    radius = float(body.radius)
    prof = body.profile
    j = np.repeat(np.arange(4, prof.shape[0] - 5, 9), 3)
    frac = np.tile([0.1, 0.5, 0.9], j.size // 3)[:, None]
    on, t = prof[j] + frac * (prof[j + 1] - prof[j]), prof[j + 1] - prof[j]
    n2 = np.column_stack([-t[:, 1], t[:, 0]]) / np.linalg.norm(t, axis=1)[:, None]
    phi = np.linspace(0.0, 2.0 * math.pi, j.size, endpoint=False)
    turn = np.column_stack([np.zeros(j.size), np.cos(phi), np.sin(phi)])
    outward = (np.column_stack([n2[:, 0], np.zeros((j.size, 2))]) + n2[:, 1:2] * turn) @ body.basis.T
    inner = on - 1e-3 * radius * n2
    starts = body.center + (np.column_stack([inner[:, 0], np.zeros((j.size, 2))]) + inner[:, 1:2] * turn) @ body.basis.T
    depth = -body.distance(starts)
    assert (depth > 0.5e-3 * radius).all()
    expected = starts + (depth + 1e-6 * radius)[:, None] * outward
    straight = [i for i in range(j.size) if not body.inside(expected[i][None])[0]
                and _segment_clear(field, starts[i], expected[i])]
    assert len(straight) >= 5
    for i in straight:
        np.testing.assert_allclose(_exit_body(field, starts[i].copy())[0], expected[i], rtol=0, atol=1e-9)


def test_clearance_and_inside_body_take_one_point_or_any_batch_of_points():
    """Two spheres (r 6 and 3 m, margin 1.5 m: flow radii 7.512 and 4.506 m) and a plane at z = −60 m:
    the clearance and the inside-body test of one point ``(3,)`` and of a ``(2, 3, 3)`` batch are those of
    the same points in a row, and by hand: |p − c| − (r + 1.5) or z + 60, whichever is least; inside a
    flow surface only where |p − c| < A (a point 0.5 m outside a flow sphere is not inside)."""
    field = FlowField([Sphere((0.0, 0.0, -50.0), 6.0), Sphere((40.0, 0.0, -50.0), 3.0)],
                      np.array([100.0, 0.0, -50.0]), FlowParams(), margin=1.5, plane=-60.0)
    a0, a1 = field.radii
    rows = np.array([[0.0, 10.0, -50.0], [40.0, 0.0, -45.0], [40.0, 0.0, -50.0 + a1 - 0.05],
                     [0.0, 0.0, -50.0 + a0 + 0.5], [20.0, 0.0, -59.0], [0.0, 7.51, -50.0]])
    by_hand = [10.0 - 7.5, 5.0 - 4.5, a1 - 0.05 - 4.5, a0 + 0.5 - 7.5, 1.0, 7.51 - 7.5]
    inside = [False, False, True, False, False, True]
    np.testing.assert_allclose(field.clearance(rows), by_hand, atol=1e-12)
    assert list(field.inside_body(rows)) == inside
    batch = rows.reshape(2, 3, 3)
    np.testing.assert_allclose(field.clearance(batch), np.reshape(by_hand, (2, 3)), atol=1e-12)
    assert field.inside_body(batch).tolist() == np.reshape(inside, (2, 3)).tolist()
    for p, c, i in zip(rows, by_hand, inside):
        assert np.shape(field.clearance(p)) == () and float(field.clearance(p)) == pytest.approx(c, abs=1e-12)
        assert np.shape(field.inside_body(p)) == () and bool(field.inside_body(p)) == i
    empty = FlowField((), np.array([100.0, 0.0, -50.0]), FlowParams())  # no surface at all: never inside
    assert np.shape(empty.inside_body(rows[0])) == () and not empty.inside_body(rows[0])
    assert empty.inside_body(batch).shape == (2, 3) and not empty.inside_body(batch).any()


def test_ellipsoid_clearance_is_exact_near_and_the_scaled_lower_bound_far():
    """The (8, 4, 3) ellipsoid, margin 0.5 m, points on its axes in one batch: near it (the bound (s − 1)·3
    under the largest semi-axis 8 m) the exact distance minus the margin, by hand 2 − 0.5, 2 − 0.5 and
    1 − 0.5 m; far from it the cheap bound, by hand (100/8 − 1)·3 − 0.5 = 34 m (the exact one is 91.5 m)."""
    field = FlowField((ELLIPSOID,), GOAL, FlowParams(), 0.5)
    p = np.array([[10.0, 0.0, 0.0], [0.0, -6.0, 0.0], [0.0, 0.0, 4.0], [100.0, 0.0, 0.0]])
    np.testing.assert_allclose(field.clearance(p), [1.5, 1.5, 0.5, 34.0], atol=1e-9)


def test_sphere_image_field_takes_one_point_or_any_batch_of_points():
    """``sphere_exact_velocity`` of one point ``(3,)`` and of a ``(2, 3, 3)`` batch: the velocities of the same
    points in a row (shape ``(..., 3)`` in, ``(..., 3)`` out)."""
    from auvplan.planners.flow import sphere_exact_velocity

    rng = np.random.default_rng(4)
    p = rng.uniform(-20.0, 20.0, (6, 3))
    p = p[np.linalg.norm(p - [1.0, 2.0, 3.0], axis=1) > 5.0]
    rows = sphere_exact_velocity(p, (1.0, 2.0, 3.0), 4.0, (20.0, 25.0, 30.0))
    batch = sphere_exact_velocity(np.stack([p, p[::-1]]), (1.0, 2.0, 3.0), 4.0, (20.0, 25.0, 30.0))
    np.testing.assert_allclose(batch, np.stack([rows, rows[::-1]]), rtol=1e-14)
    for q, u in zip(p, rows):
        np.testing.assert_allclose(sphere_exact_velocity(q, (1.0, 2.0, 3.0), 4.0, (20.0, 25.0, 30.0)), u, rtol=1e-14)


def test_push_out_of_a_small_sphere_and_below_the_plane():
    """``push_out``'s margin is eps × the largest flow radius, or × 1 m when that is smaller than 1 m or
    there is no obstacle: a sphere r = 1 m, margin 0.2 m (A = 1.202 m), eps = 10⁻³: (0, 0.5, −50) goes to
    (0, 1.202 (1 + 10⁻³), −50); with the plane z = −50 m alone, (3, 4, −50.3) goes to (3, 4, −50 + 10⁻³)."""
    field = FlowField([Sphere((0.0, 0.0, -50.0), 1.0)], np.array([30.0, 0.0, -50.0]), FlowParams(), margin=0.2)
    a = float(field.radii[0])
    assert a == pytest.approx(1.202)
    moved = field.push_out(np.array([[0.0, 0.5, -50.0]]), 1e-3)
    np.testing.assert_allclose(moved, [[0.0, a * (1 + 1e-3), -50.0]], rtol=0, atol=1e-12)
    plane = FlowField((), np.array([30.0, 0.0, -40.0]), FlowParams(), plane=-50.0)
    np.testing.assert_allclose(plane.push_out(np.array([[3.0, 4.0, -50.3]]), 1e-3), [[3.0, 4.0, -50.0 + 1e-3]],
                               rtol=0, atol=1e-12)


# ---------------------------------------------------------------------- the streamlines' rules
def test_start_in_the_flow_shell_of_a_sphere_leaves_along_the_radius():
    """A sphere (r = 5, margin 0.5: inflated 5.5 m, flow sphere A = 5.51 m) and a start 5.505 m from its
    centre, outside the inflated obstacle but inside the flow sphere: the exit rule's point is on the
    ray from the centre at A (1 + 10⁻⁶), then the streamline arrives without touching the obstacle (a second
    sphere 30 m away: the exit is from the surface the start is inside, the nearest one)."""
    field = FlowField((Sphere((1.0, 2.0, -3.0), 5.0), Sphere((15.0, -25.0, 10.0), 2.0)), GOAL, FlowParams(), 0.5)
    a = float(field.radii[0])
    assert a == pytest.approx(5.51)
    ray = np.array([2.0, -3.0, 6.0]) / 7.0
    start = np.array([1.0, 2.0, -3.0]) + 5.505 * ray
    sl = integrate_streamlines(field, start)
    assert sl.exits[0] and sl.arrived[0] and sl.min_distance[0] >= 0
    np.testing.assert_allclose(sl.paths[0][0], start, atol=1e-12)
    np.testing.assert_allclose(sl.paths[0][1], np.array([1.0, 2.0, -3.0]) + a * (1 + 1e-6) * ray, atol=1e-9)


def test_streamline_stops_at_the_step_cap():
    """``max_steps = 7`` and two starts 30 m from the goal: exactly 7 steps (8 nodes), status ``max_steps``.
    With ``max_steps = 30``, an on-axis start (its 6th or so step the front rule's sideways step) and an
    off-axis one integrated together: both stop after exactly 30 steps, the sideways step counted as one."""
    field = FlowField((Sphere((0.0, 0.0, 0.0), 5.0),), GOAL, FlowParams(max_steps=7), 0.5)
    sl = integrate_streamlines(field, np.array([[-30.0, 3.0, 1.0], [-25.0, -4.0, 2.0]]))
    assert list(sl.status) == ["max_steps", "max_steps"]
    assert list(sl.steps) == [8, 8] and [len(p) for p in sl.paths] == [8, 8]
    field = FlowField((Sphere((0.0, 0.0, 0.0), 5.0),), GOAL, FlowParams(max_steps=30), 0.5)
    sl = integrate_streamlines(field, np.array([[-30.0, 0.0, 0.0], [-25.0, -4.0, 2.0]]))
    assert list(sl.status) == ["max_steps", "max_steps"] and list(sl.deflections) == [1, 0]
    assert list(sl.steps) == [31, 31] and [len(p) for p in sl.paths] == [31, 31]
    assert np.abs(sl.paths[0][:, 2]).max() > 0.3  # the sideways step is in the path


def test_min_distance_is_the_least_clearance_of_the_nodes_and_the_last_node_is_within_the_arrival_radius():
    """Three spheres and 40 seeded starts: each streamline's ``min_distance`` is the least clearance of its
    integration nodes, recomputed from the path; an arrived streamline's last node before the goal lies
    within the arrival radius (the goal is then appended); on-axis starts included (sideways steps)."""
    spheres = (Sphere((0.0, 0.0, 0.0), 5.0), Sphere((12.0, 9.0, -2.0), 3.0), Sphere((14.0, -8.0, 3.0), 2.0))
    field = FlowField(spheres, GOAL, FlowParams(), 0.5)
    rng = np.random.default_rng(8)
    starts = rng.uniform(-30.0, 25.0, (200, 3))
    starts = np.vstack([[[-30.0, 0.0, 0.0], [-20.0, 0.0, 0.0]], starts[field.clearance(starts) > 0.5][:38]])
    sl = integrate_streamlines(field, starts)
    assert sl.arrived.all() and sl.deflections[:2].tolist() == [1, 1]
    for path, least in zip(sl.paths, sl.min_distance):
        nodes = path[:-1]  # the goal appended on arrival is not a node
        assert least == pytest.approx(field.clearance(nodes).min(), abs=1e-12)
        assert np.linalg.norm(nodes[-1] - GOAL) <= field.params.arrive
        np.testing.assert_array_equal(path[-1], GOAL)


def test_stagnation_in_the_uniform_field_is_the_speed_against_the_free_stream():
    """Uniform flow U = 1 past a sphere (flow radius A): on the downstream axis |u| = U (1 − A³/r³).  A start
    where that is 0.5·10⁻⁶ (half the ``stagnation`` fraction of U) stops as ``stagnation``; one where it is
    1.5·10⁻⁶ moves on (3 steps allowed)."""
    field = FlowField((Sphere((0.0, 0.0, 0.0), 5.0),), np.array([60.0, 0.0, 0.0]),
                      FlowParams(field="uniform", max_steps=3), 0.5, direction=(1.0, 0.0, 0.0))
    a = float(field.radii[0])
    speeds = np.array([0.5e-6, 1.5e-6])
    starts = np.column_stack([a / (1.0 - speeds) ** (1.0 / 3.0), np.zeros(2), np.zeros(2)])
    np.testing.assert_allclose(np.linalg.norm(field.velocity(starts), axis=1), speeds, rtol=1e-6)
    sl = integrate_streamlines(field, starts)
    assert list(sl.status) == ["stagnation", "max_steps"] and list(sl.steps) == [1, 4]


@pytest.mark.parametrize("height", [5.0, 0.4])
def test_stagnation_is_the_speed_against_the_bare_sinks(height):
    """The target h above a plane (the seabed's mirror): on the plane, ρ from the foot of the target, the
    sink and its image give |u| = 2 m ρ / (4π (ρ² + h²)^{3/2}), i.e. |u| / (m / 4π r²) = 2 ρ / r (r the
    distance to the target).  A start where that ratio is half the ``stagnation`` fraction stops there as
    ``stagnation`` (after 0 steps); one where it is twice the fraction moves on (h = 5 m and 0.4 m, inside
    the 1 m under which a floor on r would change the sink's speed; arrival radius 0.1 m)."""
    params = FlowParams(arrive=0.1, max_steps=3)
    target = np.array([3.0, -2.0, -50.0 + height])
    field = FlowField((), target, params, plane=-50.0)
    starts = []
    for ratio in (0.5, 2.0):
        # 2 ρ / √(ρ² + h²) = ratio × stagnation, solved for ρ
        k = 0.5 * ratio * params.stagnation
        rho = k * height / math.sqrt(1.0 - k * k)
        starts.append([3.0 + rho, -2.0, -50.0])
    starts = np.array(starts)
    r = np.linalg.norm(starts - target, axis=1)
    speed = np.linalg.norm(field.velocity(starts), axis=1)
    np.testing.assert_allclose(speed / (1.0 / (4 * math.pi * r**2)) / params.stagnation, [0.5, 2.0], rtol=1e-6)
    sl = integrate_streamlines(field, starts)
    assert list(sl.status) == ["stagnation", "max_steps"]
    assert list(sl.steps) == [1, 4]


def _deflection(path, center, axis, radius):
    """Index of the front stagnation rule's sideways step in ``path`` (the first jump of ≥ 0.05 R across the
    axis through ``center``), checked to be a step of 0.06 R square to the axis from a point on it."""
    q = path - center
    off = np.linalg.norm(q - np.outer(q @ axis, axis), axis=1)
    k = int(np.flatnonzero(off > 0.05 * radius)[0])
    step = path[k] - path[k - 1]
    assert off[k - 1] < 1e-6 * radius and np.linalg.norm(step) == pytest.approx(0.06 * radius, rel=1e-6)
    assert abs(step @ axis) <= 1e-9 * radius
    return k


@pytest.mark.parametrize("h_min", [0.01, 0.0])
def test_front_stagnation_rule_steps_aside_at_the_first_node_within_its_threshold(h_min):
    """A sphere (r = 5 m, margin 0.5 m: flow radius R = 5.51 m) and an on-axis start.  The rule's threshold
    max(2 h_min, 0.02 R) is 0.02 R = 0.1102 m with h_min = 0.01 m, and 2 h_min = 0.55 m with the default
    h_min = 0.05 (5 + 0.5) m: the sideways step (to 0.06 R off the axis, over the sphere, +z) is taken
    from the first node nearer the flow sphere than the threshold, the node before it being farther; then
    the streamline arrives."""
    field = FlowField((Sphere((0.0, 0.0, 0.0), 5.0),), GOAL, FlowParams(h_min=h_min), 0.5)
    big = float(field.radii[0])
    threshold = 0.02 * big if h_min else 2.0 * 0.05 * 5.5
    sl = integrate_streamlines(field, np.array([[-30.0, 0.0, 0.0]]))
    assert sl.arrived[0] and sl.deflections[0] == 1
    path = sl.paths[0]
    k = _deflection(path, np.zeros(3), np.array([1.0, 0.0, 0.0]), big)
    assert path[k, 2] == pytest.approx(0.06 * big, rel=1e-9)
    d = np.linalg.norm(path[:k], axis=1) - big
    assert d[-1] < threshold <= d[-2]


def test_front_stagnation_rule_on_an_oblique_axis_among_several_streamlines_and_spheres():
    """The same rule on a generic axis e = (2, −3, 6)/7 through a sphere at (1, 2, 3), with a second sphere
    on the axis 20 m beyond the goal and a second start 8 m off the axis in the same batch: the on-axis
    streamline steps 0.06 R square to the axis from the first node within 0.02 R of the nearest flow
    sphere (not the farthest one; while the other streamline is not near), and both arrive."""
    c = np.array([1.0, 2.0, 3.0])
    e = np.array([2.0, -3.0, 6.0]) / 7.0
    goal = c + 35.0 * e
    field = FlowField((Sphere(tuple(c), 5.0), Sphere(tuple(c + 55.0 * e), 2.0)), goal, FlowParams(h_min=0.01), 0.5)
    big = float(field.radii[0])
    across = np.cross(e, [1.0, 0.0, 0.0])
    across /= np.linalg.norm(across)
    sl = integrate_streamlines(field, np.array([c - 35.0 * e, c - 35.0 * e + 8.0 * across]))
    assert sl.arrived.all() and list(sl.deflections) == [1, 0]
    path = sl.paths[0]
    k = _deflection(path, c, e, big)
    d = np.linalg.norm(path[:k] - c, axis=1) - big
    assert d[-1] < 0.02 * big <= d[-2]
    assert k < len(sl.paths[1])  # the other streamline was still on its way


def test_grazing_streamlines_are_pushed_back_onto_the_surface_until_the_correction_limit():
    """The document's own body sizing leaves the (8, 4, 3) ellipsoid sticking out of the body, so the field
    flows into it: streamlines near the axis run onto the inflated ellipsoid, where each graze is pushed
    back outside, MAX_CORRECTIONS times, then the streamline stops as ``contact``; never a node inside.
    A start far off the axis, integrated in the same batch, arrives untouched."""
    field = FlowField((ELLIPSOID,), GOAL, FlowParams(rankine="document"), 0.5)
    near_axis = [[-30.0, 0.2 * math.cos(a), 0.2 * math.sin(a)] for a in (0.0, 2.0, 4.0)]
    sl = integrate_streamlines(field, np.array(near_axis + [[-30.0, 0.0, 25.0]]))
    assert list(sl.status) == ["contact"] * 3 + ["arrived"]
    assert list(sl.corrections) == [MAX_CORRECTIONS + 1] * 3 + [0]
    for path in sl.paths:
        assert field.distances(path, "true").min() >= 0.0
        assert (ELLIPSOID.distance(path) >= 0.5).all()
