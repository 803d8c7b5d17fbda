"""The path terms of a population in one compiled pass: constraints, seabed, obstacles, energy (:mod:`auvplan.cost`)."""

from __future__ import annotations

import math

import numpy as np

from .._types import ArrayLike, FloatArray
from ..runtime.jit import jit_enabled, kernel
from ..world import Sphere, World
from ..world.terrain import (
    TerrainKernelData,
    box_floor_kernel,
    elevation_kernel,
    lipschitz_bound_kernel,
    walk_min_kernel,
)
from .energy import _midpoint_currents, energy_kernel
from .model import CostModel, CostTerms, energy_mode, propulsion_power

__all__ = ["evaluate_paths"]


def _obstacle_slack(world: World, a: FloatArray, b: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Least slack (m, margin included) and geometric clearance of the segments ``a -> b``
    ``(P, S - 1, 3)`` to the static obstacles."""
    m = world.margins
    slack = np.full(a.shape[:-1], np.inf)
    clearance = np.full(a.shape[:-1], np.inf)
    compiled = jit_enabled()
    spheres = [o for o in world.obstacles if compiled and type(o) is Sphere]
    if spheres:  # all the spheres in one compiled pass, numpy's arithmetic in numpy's order
        _sphere_slack(np.ascontiguousarray(a).reshape(-1, 3), np.ascontiguousarray(b).reshape(-1, 3),
                      np.array([o.center for o in spheres], dtype=float).reshape(-1, 3),
                      np.array([o.radius for o in spheres], dtype=float), float(m.obstacle),
                      slack.reshape(-1), clearance.reshape(-1))
    others = [o for o in world.obstacles if not (compiled and type(o) is Sphere)]
    ends = np.stack([a, b], axis=-2) if others else a  # not stacked when no shape is left to ask
    for shape in others:
        d = np.minimum(shape.distance(a), shape.distance(b))
        touch = shape.segments_hit(ends, 0.0)
        hit = shape.segments_hit(ends, m.obstacle) if m.obstacle > 0 else touch
        clearance = np.minimum(clearance, np.where(touch, np.minimum(d, 0.0), d))
        # a segment can pass through an obstacle with both ends outside: charge at least a metre
        slack = np.minimum(slack, np.where(hit, np.minimum(d - m.obstacle, -1.0), d - m.obstacle))
    return slack, clearance


@kernel(fastmath=False)
def _sphere_slack(a: FloatArray, b: FloatArray, centers: FloatArray, radii: FloatArray, margin: float,
                  slack: FloatArray, clearance: FloatArray) -> None:  # pragma: no cover - compiled
    """:func:`_obstacle_slack`'s loop over spheres, compiled: for each segment ``a -> b (N, 3)`` and sphere,
    the ends' signed distance (:meth:`Sphere.distance`), the exact hit test (:meth:`Sphere.segments_hit`,
    the centre's distance to the segment as :func:`~auvplan.geometry.point_segment_distance` computes it:
    numpy's ``einsum`` sums three terms as ``(x + z) + y``, its ``norm`` as ``(x + y) + z``), folded into
    ``slack`` and ``clearance`` ``(N,)`` in place."""
    for k in range(a.shape[0]):
        for j in range(radii.shape[0]):
            cx, cy, cz, r = centers[j, 0], centers[j, 1], centers[j, 2], radii[j]
            ax, ay, az = a[k, 0] - cx, a[k, 1] - cy, a[k, 2] - cz
            bx, by, bz = b[k, 0] - cx, b[k, 1] - cy, b[k, 2] - cz
            d = min(np.sqrt((ax * ax + ay * ay) + az * az) - r, np.sqrt((bx * bx + by * by) + bz * bz) - r)
            dx, dy, dz = b[k, 0] - a[k, 0], b[k, 1] - a[k, 1], b[k, 2] - a[k, 2]
            dd = (dx * dx + dz * dz) + dy * dy
            px, py, pz = cx - a[k, 0], cy - a[k, 1], cz - a[k, 2]
            t = ((px * dx + pz * dz) + py * dy) / (dd if dd > 0.0 else 1.0)
            t = min(max(t, 0.0), 1.0)
            qx, qy, qz = cx - (a[k, 0] + t * dx), cy - (a[k, 1] + t * dy), cz - (a[k, 2] + t * dz)
            dist = np.sqrt((qx * qx + qy * qy) + qz * qz)
            touch = dist < r + 0.0
            hit = dist < r + margin if margin > 0 else touch
            clearance[k] = min(clearance[k], min(d, 0.0) if touch else d)
            slack[k] = min(slack[k], min(d - margin, -1.0) if hit else d - margin)


@kernel
def _point_slack(x: float, y: float, z: float, box: FloatArray, min_depth: float, max_depth: float) -> float:
    """Slack of the convex constraints at one point: depth band and bounds ``box (6,)``."""
    slack: float = min(-z - min_depth, max_depth + z, x - box[0], box[1] - x, y - box[2], box[3] - y,
                       z - box[4], box[5] - z)
    return slack


@kernel
def _path_terms(p: FloatArray, current: FloatArray, other_slack: FloatArray, other_clear: FloatArray,
                has_other: bool, terrain: TerrainKernelData, cell_max: FloatArray, has_terrain: bool,
                min_altitude: float, threshold: float, box: FloatArray, min_depth: float, max_depth: float,
                speed: float, power: float, document: int, out: FloatArray) -> None:
    """Every per-path sum of :func:`evaluate_paths` in one pass over the segments of ``p (P, S, 3)``.

    ``out (7, P)`` receives length, violations, violation depth, energy units, joules, seconds and
    the least clearance.  The convex constraints are decided by the end points (each point is
    visited once), the seabed by the terrain's compiled segment test, the obstacles come in as
    ``other_slack`` / ``other_clear`` (P, S - 1), the currents at the midpoints as ``current (P, S - 1, 3)``
    or, for a uniform field, ``(1, 1, 3)``.  A segment's seabed clearance is exact below
    ``threshold`` and otherwise a lower bound that clears it: the terrain's Lipschitz bound, else the
    highest seabed under the segment's box (``cell_max``), else the exact walk.
    """
    coef, x0, y0, dx, dy, lipschitz = terrain
    uniform = current.shape[0] == 1 and current.shape[1] == 1  # one current for every segment
    for i in range(p.shape[0]):
        length = viol = depth = units = joules = seconds = 0.0
        clear = math.inf
        px, py, pz = p[i, 0, 0], p[i, 0, 1], p[i, 0, 2]
        s_p = _point_slack(px, py, pz, box, min_depth, max_depth)
        g_p = pz - elevation_kernel(coef, x0, y0, dx, dy, px, py) if has_terrain else math.inf
        for s in range(p.shape[1] - 1):
            qx, qy, qz = p[i, s + 1, 0], p[i, s + 1, 1], p[i, s + 1, 2]
            s_q = _point_slack(qx, qy, qz, box, min_depth, max_depth)
            slack = min(s_p, s_q)
            c = math.inf
            if has_terrain:
                g_q = qz - elevation_kernel(coef, x0, y0, dx, dy, qx, qy)
                # min_altitude_kernel with a second bound before the walk: the highest seabed under the box
                c = lipschitz_bound_kernel(lipschitz, px, py, pz, qx, qy, qz, g_p, g_q)
                if not c >= threshold:
                    c = box_floor_kernel(cell_max, x0, y0, dx, dy, px, py, pz, qx, qy, qz)
                    if not c >= threshold:
                        c = walk_min_kernel(coef, x0, y0, dx, dy, px, py, pz, qx, qy, qz)
                slack = min(slack, c - min_altitude)
                g_p = g_q
            if has_other:
                slack = min(slack, other_slack[i, s])
                c = min(c, other_clear[i, s])
            ex, ey, ez = qx - px, qy - py, qz - pz
            ds = math.sqrt(ex * ex + ey * ey + ez * ez)
            ci, cs = (0, 0) if uniform else (i, s)
            u, j, t, blocked = energy_kernel(ex, ey, ez, ds, current[ci, cs, 0], current[ci, cs, 1],
                                              current[ci, cs, 2], speed, power, document)
            length += ds
            units += u
            joules += j
            seconds += t
            clear = min(clear, c)
            if slack < 0.0:
                depth -= slack
            if slack < 0.0 or blocked:
                viol += 1.0
            px, py, pz, s_p = qx, qy, qz, s_q
        out[0, i], out[1, i], out[2, i], out[3, i] = length, viol, depth, units
        out[4, i], out[5, i], out[6, i] = joules, seconds, clear


def evaluate_paths(world: World, points: ArrayLike, model: CostModel, exact: bool = False) -> CostTerms:
    """Cost terms of sampled paths in a world (static obstacles only).

    Violations are always detected exactly.

    Parameters
    ----------
    world : World
        Seabed, currents, static obstacles, bounds and margins.
    points : array_like
        Sampled paths ``(P, S, 3)`` (m), or one path ``(S, 3)``.
    model : CostModel
        Weights and vehicle figures.
    exact : bool, default False
        Also make the reported ``min_clearance`` exact (otherwise it may be a lower bound where
        it is large).

    Returns
    -------
    CostTerms
        Per-path terms ``(P,)``.
    """
    p = np.asarray(points, dtype=float)
    if p.ndim == 2:
        p = p[None]
    p = np.ascontiguousarray(p)
    a, b = p[:, :-1], p[:, 1:]
    current = _midpoint_currents(world, a, b)
    other_slack, other_clear = _static_slack(world, p, a, b)
    m, bd = world.margins, world.bounds
    terrain = world.terrain.kernel_data if world.terrain is not None else _no_terrain()
    cell_max = world.terrain.cell_max if world.terrain is not None else terrain[0][..., 0]
    out = np.empty((7, p.shape[0]))
    _path_terms(p, current, other_slack, other_clear, bool(world.obstacles) or bool(world.zones), terrain, cell_max,
                world.terrain is not None,
                float(m.min_altitude), np.inf if exact else float(m.min_altitude),  # floats: one compiled kernel
                np.array([bd.xmin, bd.xmax, bd.ymin, bd.ymax, bd.zmin, bd.zmax], dtype=float), float(m.min_depth),
                float(m.max_depth),
                float(model.speed), propulsion_power(model), energy_mode(model), out)
    length, violations, depth, units, energy_j, duration, clearance = out
    counts = violations.astype(np.intp)
    terrain_cost = model.terrain_penalty * counts + model.violation_slope * depth
    energy = model.scale * units
    total = model.w_length * length + model.w_terrain * terrain_cost + model.w_energy * energy
    return CostTerms(
        total=total,
        length=length,
        terrain=terrain_cost,
        energy=energy,
        energy_j=energy_j,
        duration_s=duration,
        violations=counts,
        min_clearance=clearance,
    )


def _static_slack(world: World, p: FloatArray, a: FloatArray, b: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The static obstacles' slack and clearance per segment, the zones' slack folded in (the exact segment-vs-prism
    test: a violation as deep as the trace inside a zone); empty without either."""
    if world.obstacles:
        other_slack, other_clear = _obstacle_slack(world, a, b)
    else:
        other_slack = other_clear = np.empty((0, 0))
    if world.zones:
        zone_slack = world.zones.polyline_slack(p)
        if world.obstacles:
            other_slack = np.minimum(other_slack, zone_slack)
        else:
            other_slack, other_clear = zone_slack, np.full(zone_slack.shape, np.inf)
    return other_slack, other_clear


def _no_terrain() -> TerrainKernelData:
    """The kernel's terrain argument for a world without a seabed (typed like a real one, never read)."""
    coef = np.zeros((1, 1, 4))
    coef.setflags(write=False)
    return coef, 0.0, 0.0, 1.0, 1.0, 0.0
