"""Oracle tests of document 000's flow planner: the field's parts and the streamlines' stop rules.

The survivors of the mutation run on ``flow`` (docs/mutants.md §2) each met one of these: a small
independent computation (an image by hand, an analytic speed, a rule's threshold read off the path)
that a one-line bug in ``planners/flow/field.py`` or ``planners/flow/stream.py`` breaks.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from auvplan.planners.core.params import FlowParams
from auvplan.planners.flow.elements import sink_velocity
from auvplan.planners.flow.field import FlowField
from auvplan.planners.flow.stream import MAX_CORRECTIONS, integrate_streamlines
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
    axis): ``push_out`` moves each back out along that normal by δ + m·R with m = eps·2^k (eps = 10⁻⁶),
    k the fewest doublings that leave the body's own surface (F = 0 lies a little outside the profile
    polyline: with k = 0 alone most points stayed inside), so within 2·10⁻⁵ R of the profile (the graze
    correction's move); the body's own ``normal`` there is the same outward unit vector (it was the inward
    one: the correction pushed grazing points deeper in).  A sphere 40 m away comes first in the field's
    surfaces."""
    field = FlowField((ELLIPSOID, Sphere((0.0, 40.0, 0.0), 2.0)), GOAL, FlowParams(rankine="line"), 0.5)
    body = field.bodies[0]
    radius = float(body.radius)
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
    assert (field.distances(points, "true")[:, 1] < -0.9 * delta).all()
    np.testing.assert_allclose(body.normal(points), outward, atol=1e-12)
    assert field.radii.max() == radius
    moved = field.push_out(points, 1e-6)
    step = np.linalg.norm(moved - points, axis=1)
    np.testing.assert_allclose((moved - points) / step[:, None], outward, rtol=0, atol=1e-9)
    # the margin is 10⁻⁶ R doubled k times, k the fewest that leaves the body's own surface (F = 0)
    k = np.log2((step - delta) / (1e-6 * radius))
    np.testing.assert_allclose(k, np.round(k), atol=1e-3)
    assert not body.inside(moved).any() and (field.distances(moved, "true")[:, 1] >= 0).all()
    fewer = points + (delta + 0.5 * (step - delta))[:, None] * outward
    assert (k > 0.5).sum() >= 3 and body.inside(fewer[k > 0.5]).all()
    assert (np.abs(body.distance(moved)) <= 2e-5 * radius).all()  # on the profile polyline, to the margin


def test_exit_rule_leaves_a_body_straight_along_its_normal_where_that_lands_outside():
    """Starts 10⁻³ R inside the flow body of the (8, 4, 3) ellipsoid, built by hand from its meridian profile
    (a tenth, half and nine tenths along a segment, in along the segment's left-hand normal n, turned about
    the axis): where the straight move to p + (depth + 10⁻⁶ R) n lands outside the body, clear of the
    obstacle, that is the exit rule's point (by hand, n independent of the body's own ``normal``)."""
    from auvplan.planners.flow.stream import _exit_body, _segment_clear

    field = FlowField((ELLIPSOID,), GOAL, FlowParams(rankine="line"), 0.5)
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


def test_exit_rule_leaves_a_body_in_one_move():
    """40 seeded starts inside the flow body of the (8, 4, 3) ellipsoid (outside the inflated obstacle): the
    exit rule's first point (straight along the normal, or by bisection along the obstacle's normal, then
    10⁻⁶ R on) is already outside every flow surface: one move."""
    from auvplan.planners.flow.stream import _exit_body

    field = FlowField((ELLIPSOID,), GOAL, FlowParams(rankine="line"), 0.5)
    rng = np.random.default_rng(6)
    p = rng.uniform(-1.0, 1.0, (4000, 3)) * (9.5, 5.0, 4.0)
    p = p[field.inside_body(p) & (field.clearance(p) > 0)][:40]
    assert len(p) == 40
    for start in p:
        out = _exit_body(field, start.copy())
        assert len(out) == 1 and not field.inside_body(out[0]), start


def test_exit_rule_bisection_lands_just_past_the_body_along_the_obstacle_normal():
    """Seeded starts inside the (8, 4, 3) ellipsoid's flow body whose straight move fails: the exit point q is
    on the obstacle's outward normal g at the start (q − p ∥ g) and 10⁻⁶ R past the body's surface:
    q − 1.01·10⁻⁶ R g is inside the body, q − 0.99·10⁻⁶ R g outside."""
    from auvplan.planners.flow.stream import _exit_body, _segment_clear

    field = FlowField((ELLIPSOID,), GOAL, FlowParams(rankine="line"), 0.5)
    body = field.bodies[0]
    radius = float(body.radius)
    rng = np.random.default_rng(7)
    p = rng.uniform(-1.0, 1.0, (4000, 3)) * (9.5, 5.0, 4.0)
    p = p[field.inside_body(p) & (field.clearance(p) > 0)][:60]
    bisected = 0
    for start in p:
        straight = start + (-body.distance(start) + 1e-6 * radius) * body.normal(start[None])[0]
        if _segment_clear(field, start, straight) and not body.inside(straight[None])[0]:
            continue
        q = _exit_body(field, start.copy())[0]
        g = ELLIPSOID.gradient(start)
        step = q - start
        np.testing.assert_allclose(step / np.linalg.norm(step), g, atol=1e-9)
        assert body.inside((q - 1.01e-6 * radius * g)[None])[0] and not body.inside((q - 0.99e-6 * radius * g)[None])[0]
        bisected += 1
    assert bisected >= 10


def test_document_sphere_field_in_the_flow_field_is_the_blend_of_the_single_fields():
    """``field = "document"`` with two spheres (flow radii A = r + margin + 0.002 r): the field's velocity is
    Σ w_k u_k with u_k the document's single-sphere field and w_k = (1/d_k) / Σ (1/d_j), d_k = |p − c_k| − A_k,
    all by hand; with one sphere, its single field."""
    from auvplan.planners.flow.elements import sphere_document_velocity

    c = np.array([[0.0, 0.0, 0.0], [15.0, 6.0, -2.0]])
    r = np.array([5.0, 3.0])
    a = r + 0.5 + 0.002 * r
    rng = np.random.default_rng(9)
    p = rng.uniform(-20.0, 25.0, (80, 3))
    p = p[(np.linalg.norm(p[:, None] - c, axis=2) > a + 0.2).all(axis=1)]
    field = FlowField([Sphere(tuple(c[0]), 5.0), Sphere(tuple(c[1]), 3.0)], GOAL, FlowParams(field="document"), 0.5)
    u = np.stack([sphere_document_velocity(p, c[k], a[k], GOAL) for k in range(2)], axis=1)
    inv = 1.0 / (np.linalg.norm(p[:, None] - c, axis=2) - a)
    w = inv / inv.sum(axis=1, keepdims=True)
    np.testing.assert_allclose(field.velocity(p), (w[:, :, None] * u).sum(axis=1), rtol=1e-10)
    one = FlowField([Sphere(tuple(c[0]), 5.0)], GOAL, FlowParams(field="document"), 0.5)
    np.testing.assert_allclose(one.velocity(p), u[:, 0], rtol=1e-12)


def test_front_stagnation_rule_does_not_act_behind_a_small_obstacle():
    """A small sphere (r = 0.3 m, margin 0.1 m: flow radius 0.4006 m, h_min 0.02 m) and a start on its
    downstream axis 0.0094 m behind it (within 2 h_min, but downstream): no sideways step, it arrives."""
    field = FlowField((Sphere((0.0, 0.0, 0.0), 0.3),), GOAL, FlowParams(), 0.1)
    sl = integrate_streamlines(field, np.array([0.41, 0.0, 0.0]))
    assert sl.arrived[0] and sl.deflections[0] == 0


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
    under the largest semi-axis 8 m) the exact distance minus the margin, by hand 2 − 0.5, 2 − 0.5,
    1 − 0.5 and (at (0, 9, 0), bound 3.25 m) 5 − 0.5 m; far from it the cheap bound, by hand
    (100/8 − 1)·3 − 0.5 = 34 m (the exact one is 91.5 m)."""
    field = FlowField((ELLIPSOID,), GOAL, FlowParams(), 0.5)
    p = np.array([[10.0, 0.0, 0.0], [0.0, -6.0, 0.0], [0.0, 0.0, 4.0], [0.0, 9.0, 0.0], [100.0, 0.0, 0.0]])
    np.testing.assert_allclose(field.clearance(p), [1.5, 1.5, 0.5, 4.5, 34.0], atol=1e-9)


def test_sphere_image_field_takes_one_point_or_any_batch_of_points():
    """``sphere_exact_velocity`` of one point ``(3,)`` and of a ``(2, 3, 3)`` batch: the velocities of the same
    points in a row (shape ``(..., 3)`` in, ``(..., 3)`` out)."""
    from auvplan.planners.flow.elements import sphere_exact_velocity

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
def test_start_in_the_flow_shell_of_a_sphere_leaves_smoothly_with_the_flow():
    """A sphere (r = 5, margin 0.5: inflated 5.5 m, flow sphere A = 5.51 m) and a start 5.505 m from its
    centre, outside the inflated obstacle but inside the flow sphere (a second sphere 30 m away).  The smooth
    exit: the first node is 0.01 A on from the start along cos 30° t + sin 30° n, n the ray from the centre
    and t the flow's direction at A (1 + 10⁻³) on that ray with its radial part removed (by hand); every
    exit node is farther from the centre than the last, the exit hands over between 0.08 A and 0.09 A
    outside the flow sphere, and no turn on the whole path reaches 30° (the straight exit along the radius
    met the flow at 90°).  The streamline then arrives without touching the obstacle."""
    from auvplan.planners.flow.stream import EXIT_ANGLE

    centre = np.array([1.0, 2.0, -3.0])
    field = FlowField((Sphere(tuple(centre), 5.0), Sphere((15.0, -25.0, 10.0), 2.0)), GOAL, FlowParams(), 0.5)
    a = float(field.radii[0])
    assert a == pytest.approx(5.51) and EXIT_ANGLE == pytest.approx(math.radians(30.0))
    ray = np.array([2.0, -3.0, 6.0]) / 7.0
    start = centre + 5.505 * ray
    sl = integrate_streamlines(field, start)
    assert sl.exits[0] and sl.arrived[0] and sl.min_distance[0] >= 0
    path = sl.paths[0]
    np.testing.assert_allclose(path[0], start, atol=1e-12)
    u = field.velocity((centre + a * (1 + 1e-3) * ray)[None])[0]
    t = u - (u @ ray) * ray
    t /= np.linalg.norm(t)
    first = start + 0.01 * a * (math.cos(math.radians(30.0)) * t + math.sin(math.radians(30.0)) * ray)
    np.testing.assert_allclose(path[1], first, atol=1e-9)
    r = np.linalg.norm(path - centre, axis=1)
    k = int(np.argmax(r >= a + 0.08 * a))  # the hand-over node
    assert (np.diff(r[: k + 1]) > 0).all() and r[k] <= a + 0.09 * a
    legs = np.diff(path, axis=0)
    legs = legs[np.linalg.norm(legs, axis=1) > 1e-9]
    legs /= np.linalg.norm(legs, axis=1, keepdims=True)
    assert np.degrees(np.arccos(np.clip((legs[:-1] * legs[1:]).sum(axis=1), -1, 1))).max() < 30.0


def test_exit_rule_in_the_wedge_between_a_sphere_and_the_plane():
    """A sphere (r = 5 m, margin 0.5 m, flow radius A = 5.51 m) whose flow shell reaches below the plane
    z = −5.507 m: a start at (0, 0, −5.505) is inside the shell, 2 mm above the plane.  The sphere's normal
    (straight down) would cross the plane, so the exit rule searches: its one point is outside every flow
    surface, above the plane, reached by a segment that keeps the margin everywhere (it used to step under
    the plane and end there as ``contact``), and it is the shortest such move: sideways, at most
    √(5.51² − 5.505²) = 0.235 m plus one march step (0.5 % of 3 × 5.51 m)."""
    from auvplan.planners.flow.stream import _exit_body

    field = FlowField((Sphere((0.0, 0.0, 0.0), 5.0),), GOAL, FlowParams(), 0.5, plane=-5.507)
    start = np.array([0.0, 0.0, -5.505])
    assert field.clearance(start) > 0 and field.inside_body(start)
    out = _exit_body(field, start.copy())
    assert len(out) == 1 and not field.inside_body(out[0]) and out[0][2] > -5.507
    seg = start + np.linspace(0.0, 1.0, 201)[:, None] * (out[0] - start)
    assert field.clearance(seg).min() >= 0.0
    assert np.linalg.norm(out[0] - start) <= math.sqrt(5.51**2 - 5.505**2) + 2 * 3 * 5.51 / 600


def test_min_distance_counts_the_start_and_the_exit_rules_points():
    """The start and the exit rule's points are nodes of the path, so ``min_distance`` counts them.  By
    hand: a start 5.505 m from a sphere inflated to 5.5 m is 0.005 m clear (its exit point, on the flow
    sphere, and everything after are farther); in the wedge under a sphere's flow shell, the exit rule's
    point (a sideways move that stays above the plane z = −5.507 m) keeps the start's clearance of 2 mm
    above the plane or more (it was counted from the last exit point on; the exit used to step under the
    plane and end as ``contact``)."""
    field = FlowField((Sphere((1.0, 2.0, -3.0), 5.0), Sphere((15.0, -25.0, 10.0), 2.0)), GOAL, FlowParams(), 0.5)
    ray = np.array([2.0, -3.0, 6.0]) / 7.0
    sl = integrate_streamlines(field, np.array([1.0, 2.0, -3.0]) + 5.505 * ray)
    assert sl.arrived[0] and sl.min_distance[0] == pytest.approx(0.005, abs=1e-12)
    assert sl.min_distance[0] == pytest.approx(field.clearance(sl.paths[0]).min(), abs=1e-12)
    field = FlowField((Sphere((0.0, 0.0, 0.0), 5.0),), GOAL, FlowParams(), 0.5, plane=-5.507)
    sl = integrate_streamlines(field, np.array([0.0, 0.0, -5.505]))
    assert sl.arrived[0] and sl.min_distance[0] == pytest.approx(field.clearance(sl.paths[0]).min(), abs=1e-12)
    assert 0.0 <= sl.min_distance[0] <= 0.002 + 1e-12


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


def test_free_sink_streamline_halves_the_goal_distance_each_step():
    """No obstacle: the field is the bare sink, its streamlines straight lines to the target, and each RK4
    step is step_factor × the goal distance (h_min 0.01 m): the distance to the target halves exactly at
    every node, 40 m → 20 → 10 → … until within the arrival radius (0.5 m after 7 steps)."""
    field = FlowField((), GOAL, FlowParams())
    start = GOAL + 40.0 * np.array([-2.0, 3.0, 6.0]) / 7.0
    sl = integrate_streamlines(field, start)
    nodes = sl.paths[0][:-1]
    assert sl.arrived[0] and len(nodes) == 8
    np.testing.assert_allclose(np.linalg.norm(nodes - GOAL, axis=1), 40.0 / 2.0 ** np.arange(8), rtol=1e-12)


def test_arrival_takes_precedence_over_the_front_stagnation_rule():
    """A start on the axis 0.048 m in front of a 1 m sphere (inside the rule's 2 h_min = 0.1 m) but within the
    arrival radius (3.5 m) of the target 2 m behind the sphere's centre: it arrives at once, no sideways
    step (the scene 100 m from the origin)."""
    field = FlowField((Sphere((100.0, 0.0, 0.0), 1.0),), np.array([102.0, 0.0, 0.0]), FlowParams(arrive=3.5))
    sl = integrate_streamlines(field, np.array([98.95, 0.0, 0.0]))
    assert sl.status[0] == "arrived" and sl.deflections[0] == 0 and sl.steps[0] == 1


def test_min_distance_counts_the_node_before_a_sideways_step():
    """An on-axis start stopped by the step cap right at its sideways step (a first run finds that step):
    ``min_distance`` is the least clearance of the nodes, the node before the step (nearest the sphere)."""
    field = FlowField((Sphere((0.0, 0.0, 0.0), 5.0),), GOAL, FlowParams(max_steps=30), 0.5)
    first = integrate_streamlines(field, np.array([-30.0, 0.0, 0.0])).paths[0]
    k = int(np.flatnonzero(np.abs(first[:, 2]) > 0.1)[0])
    field = FlowField((Sphere((0.0, 0.0, 0.0), 5.0),), GOAL, FlowParams(max_steps=k), 0.5)
    sl = integrate_streamlines(field, np.array([-30.0, 0.0, 0.0]))
    path = sl.paths[0]
    assert sl.status[0] == "max_steps" and sl.deflections[0] == 1 and len(path) == k + 1
    assert field.clearance(path[-2]) < field.clearance(path[-1])
    assert sl.min_distance[0] == pytest.approx(field.clearance(path).min(), abs=1e-12)


def test_the_smallest_step_is_h_min_from_the_smallest_obstacle():
    """A sphere (r = 5 m) and the (8, 4, 3) ellipsoid, margin 0.5 m: h_min = 0.05 × (3 + 0.5) = 0.175 m (the
    smallest semi-axis of all).  A start 0.1 m from the sphere's flow surface would step 0.5 × 0.1 m; its
    first step is h_min (to 1 %: the streamline bends a little)."""
    field = FlowField((Sphere((0.0, 30.0, 0.0), 5.0), ELLIPSOID), GOAL, FlowParams(), 0.5)
    a = float(field.radii[0])
    start = np.array([0.0, 30.0, a + 0.1])
    sl = integrate_streamlines(field, start)
    assert np.linalg.norm(sl.paths[0][1] - start) == pytest.approx(0.05 * 3.5, rel=1e-2)


def test_uniform_flow_stops_at_the_first_node_past_the_goal_plane():
    """Uniform flow along +x, no obstacle, the target at the origin and a start 0.8 m off its line (outside
    the 0.5 m arrival radius): the streamline runs straight, every node but the last before the goal's
    plane x = 0 and the last past it (``missed``)."""
    field = FlowField((), np.zeros(3), FlowParams(field="uniform"), direction=(1.0, 0.0, 0.0))
    sl = integrate_streamlines(field, np.array([-20.0, 0.8, 0.0]))
    x = sl.paths[0][:, 0]
    assert sl.status[0] == "missed" and (x[:-1] <= 0).all() and x[-1] > 0
    np.testing.assert_allclose(sl.paths[0][:, 1:], np.tile([0.8, 0.0], (len(x), 1)), atol=1e-12)


def test_uniform_flow_streamlines_keep_their_stokes_stream_function():
    """Uniform flow U = 1 along x past a sphere (flow radius A): Stokes' stream function
    ψ = ½ ρ² (1 − A³/r³) is constant along each streamline, by hand; three starts round the sphere keep it
    to 1 % (RK4 keeps it to 0.3 %; an integrator of lower order drifts)."""
    field = FlowField((Sphere((0.0, 0.0, 0.0), 5.0),), np.array([60.0, 0.0, 0.0]), FlowParams(field="uniform"), 0.5,
                      direction=(1.0, 0.0, 0.0))
    a = float(field.radii[0])
    sl = integrate_streamlines(field, np.array([[-30.0, 1.0, 0.5], [-30.0, 3.0, -2.0], [-25.0, 0.0, 6.0]]))
    for path in sl.paths:
        assert path[:, 0].max() > 60.0  # past the sphere and the goal's plane
        psi = 0.5 * (path[:, 1] ** 2 + path[:, 2] ** 2) * (1.0 - a**3 / np.linalg.norm(path, axis=1) ** 3)
        assert np.abs(psi / psi[0] - 1.0).max() < 1e-2


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


@pytest.mark.parametrize(("h_min", "shift"), [(0.01, 0.0), (0.0, 0.0), (0.01, 8.4)])
def test_front_stagnation_rule_steps_aside_at_the_first_node_within_its_threshold(h_min, shift):
    """A sphere (r = 5 m, margin 0.5 m: flow radius R = 5.51 m) and an on-axis start.  The rule's threshold
    max(2 h_min, 0.02 R) is 0.02 R = 0.1102 m with h_min = 0.01 m, and 2 h_min = 0.55 m with the default
    h_min = 0.05 (5 + 0.5) m: the sideways step (to 0.06 R off the axis, over the sphere, +z) is taken
    from the first node nearer the flow sphere than the threshold, the node before it being farther; then
    the streamline arrives.  The same with the whole scene moved 8.4 m along x."""
    c = np.array([shift, 0.0, 0.0])
    field = FlowField((Sphere(tuple(c), 5.0),), GOAL + c, FlowParams(h_min=h_min), 0.5)
    big = float(field.radii[0])
    threshold = 0.02 * big if h_min else 2.0 * 0.05 * 5.5
    sl = integrate_streamlines(field, np.array([[-30.0 + shift, 0.0, 0.0]]))
    assert sl.arrived[0] and sl.deflections[0] == 1
    path = sl.paths[0]
    k = _deflection(path, c, np.array([1.0, 0.0, 0.0]), big)
    assert path[k, 2] == pytest.approx(0.06 * big, rel=1e-9)
    d = np.linalg.norm(path[:k] - c, axis=1) - big
    assert d[-1] < threshold <= d[-2]


def test_front_stagnation_rule_on_an_oblique_axis_among_several_streamlines_and_spheres():
    """The same rule on a generic axis e = (2, −3, 6)/7 through a sphere at (1, 2, 3), with a second sphere
    (listed first) on the axis 20 m beyond the goal, a second start 8 m off the axis and a third one 20 m
    behind the second sphere, all in one batch: the on-axis streamline steps 0.06 R square to the axis
    from the first node within 0.02 R of its nearest flow sphere (not the farthest one; while the other
    streamlines are on their way, one nearest the other sphere), and all arrive."""
    c = np.array([1.0, 2.0, 3.0])
    e = np.array([2.0, -3.0, 6.0]) / 7.0
    goal = c + 35.0 * e
    field = FlowField((Sphere(tuple(c + 55.0 * e), 2.0), Sphere(tuple(c), 5.0)), goal, FlowParams(h_min=0.01), 0.5)
    big = float(field.radii[1])
    across = np.cross(e, [1.0, 0.0, 0.0])
    across /= np.linalg.norm(across)
    starts = np.array([c - 35.0 * e, c - 35.0 * e + 8.0 * across, c + 75.0 * e + 3.0 * across])
    sl = integrate_streamlines(field, starts)
    assert sl.arrived.all() and list(sl.deflections) == [1, 0, 0]
    path = sl.paths[0]
    k = _deflection(path, c, e, big)
    d = np.linalg.norm(path[:k] - c, axis=1) - big
    assert d[-1] < 0.02 * big <= d[-2]
    assert k < min(len(sl.paths[1]), len(sl.paths[2]))  # the other streamlines were still on their way
    third = sl.paths[2][k - 1]
    assert np.argmin(field.distances(third, "true")) == 0  # ... one of them nearest the other sphere


def test_front_stagnation_rule_steps_aside_in_the_streamline_s_own_meridian_plane():
    """A start 0.1 m off the axis on the −y side, level with the sphere's centre (its streamline stays in
    z = 0): the sideways step puts it 0.06 R off the axis on the −y side, in its own meridian plane (not
    over the sphere, the side an exactly on-axis start takes)."""
    field = FlowField((Sphere((0.0, 0.0, 0.0), 5.0),), GOAL, FlowParams(), 0.5)
    big = float(field.radii[0])
    sl = integrate_streamlines(field, np.array([-30.0, -0.1, 0.0]))
    assert sl.arrived[0] and sl.deflections[0] == 1
    path = sl.paths[0]
    k = int(np.flatnonzero(np.hypot(path[:, 1], path[:, 2]) > 0.05 * big)[0])
    assert path[k, 1] == pytest.approx(-0.06 * big, rel=1e-9) and path[k, 2] == 0.0 and path[k, 0] == path[k - 1, 0]


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
