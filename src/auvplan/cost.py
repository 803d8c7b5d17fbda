"""Vectorised path cost over sampled populations ``(P, S, 3)`` (document 002 eq. 9, corrected).

``W = w_L Pc + w_S Sc + w_E Ec``:

* **Pc**, length (eqs. 10–11): sum of segment lengths (m).
* **Sc**, terrain and constraint cost (eq. 12): the document charges M per
  sample below the seabed.  auvplan checks every *segment* exactly
  (:meth:`Terrain.segment_min_altitude`, so nothing dips under the seabed
  between samples) against the minimum altitude, and the other constraints
  (depth limits, bounds, static obstacles) at the samples and with the
  obstacles' segment tests.  Each violating segment costs M and every metre
  of violation depth ``violation_slope`` more, which gives the search a slope
  towards feasibility.
* **Ec**, energy in the current field, per segment with the current at its
  midpoint, track tangent ŝ, c∥ = c·ŝ and c⊥ = |c - c∥ ŝ|:

  - ``"physical"`` (default): ground speed V_g = c∥ + √(V² - c⊥²) (the vehicle
    crabs to hold the track), time ds / V_g, energy (P_hotel + k V³) ds / V_g;
    infeasible where V < c⊥ or V_g ≤ 0.  Reported in joules and converted to
    cost units by ``energy_scale`` (default: metres of still-water travel per
    joule, V / (P_hotel + k V³), so that the term reads as "equivalent metres").
  - ``"document"``: eqs. 16–17 as written, |V_h| = √(V² - (V_oc sin Φ)²) +
    V_oc cos Φ and W = ρ |V_h|³ ds / V_oc with V_oc the current speed (not
    physical: it cubes the ground speed, divides by the current — floored at
    1 mm/s — and prefers head currents; docs/methods.md §2).
  - ``"document-vehicle"``: eq. 17 with the document's own gloss of V_oc under it, the
    vehicle's still-water speed: W = ρ |V_h|³ ds / V (the ground speed |V_h| as above, with the
    current; only the divisor is the constant V, so still water is finite: ρ V² ds).

The currents at all midpoints come from the field in one vectorised call; everything else is one
compiled pass (:func:`auvplan.runtime.jit.kernel`) over the segments of the population that sums every
term per path, so a population of 50 paths × 200 samples costs about a third of a millisecond.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TypedDict

import numpy as np

from ._types import ArrayLike, BoolArray, FloatArray, IntArray
from .runtime.jit import jit_enabled, kernel
from .world import Sphere, UniformCurrent, World
from .world.currents.crab import crab_speed, makes_headway
from .world.terrain import (
    TerrainKernelData,
    box_floor_kernel,
    elevation_kernel,
    lipschitz_bound_kernel,
    walk_min_kernel,
)

__all__ = ["CostModel", "CostTerms", "CostRow", "evaluate_paths", "segment_energy", "energy_kernel",
           "propulsion_power", "ENERGY_READINGS", "energy_mode"]

ENERGY_READINGS = ("physical", "document", "document-vehicle")
"""The energy models (module notes): physical, and document 002's eq. 17 with V_oc the current's
speed (as written) or the vehicle's still-water speed (the document's gloss under eq. 17)."""


@dataclass(frozen=True)
class CostModel:
    """Weights and vehicle figures of the path cost.

    Attributes
    ----------
    speed : float
        Through-water speed V (m/s).
    hotel_power, drag_k : float
        P_hotel (W) and k (W s³/m³) of the power model P = P_hotel + k V³.
    energy : str
        ``"physical"``, ``"document"`` or ``"document-vehicle"`` (:data:`ENERGY_READINGS`).
    w_length, w_terrain, w_energy : float
        Term weights.
    terrain_penalty : float
        M, cost of one violating segment.
    violation_slope : float
        Cost per metre of violation depth.
    energy_scale : float
        Cost units per joule (physical) or per unit of the document's energy; 0 = auto.

    Raises
    ------
    ValueError
        If the speed is not positive or ``energy`` is not one of the two models.
    """

    speed: float = 1.5
    hotel_power: float = 15.0
    drag_k: float = 5.8
    energy: str = "physical"
    w_length: float = 1.0
    w_terrain: float = 1.0
    w_energy: float = 1.0
    terrain_penalty: float = 1.0e4
    violation_slope: float = 100.0
    energy_scale: float = 0.0

    def __post_init__(self) -> None:
        if not self.speed > 0:
            raise ValueError(f"speed must be positive, got {self.speed}")
        if self.energy not in ENERGY_READINGS:
            raise ValueError(f"energy must be one of {', '.join(map(repr, ENERGY_READINGS))}, got {self.energy!r}")

    @property
    def scale(self) -> float:
        """Energy-to-cost conversion in force.

        Returns
        -------
        float
            ``energy_scale`` when set, else V / (P_hotel + k V³) (cost units per joule, physical) or
            1 / V² (both document readings).
        """
        if self.energy_scale > 0:
            return self.energy_scale
        if self.energy == "physical":
            return self.speed / (self.hotel_power + self.drag_k * self.speed**3)
        return 1.0 / self.speed**2  # document: |V_h|³/V_oc ~ V² per metre (1 m/s current, or V_oc = V)


def energy_mode(model: CostModel) -> int:
    """The compiled kernels' code of the model's energy reading.

    Parameters
    ----------
    model : CostModel
        Its ``energy``.

    Returns
    -------
    int
        0 physical, 1 document (V_oc the current's speed), 2 document-vehicle (V_oc = V).
    """
    return ENERGY_READINGS.index(model.energy)


class CostRow(TypedDict):
    """The cost terms of one path as plain numbers (:meth:`CostTerms.row`); units as in :class:`CostTerms`."""

    total: float
    length: float
    terrain: float
    energy: float
    energy_j: float
    duration_s: float
    violations: int
    min_clearance_m: float


@dataclass(frozen=True, eq=False)
class CostTerms:
    """Per-path cost terms (arrays of shape ``(P,)``).

    Parameters
    ----------
    total : numpy.ndarray
        Weighted cost ``W = w_L Pc + w_S Sc + w_E Ec`` (cost units).
    length : numpy.ndarray
        Path length Pc (m).
    terrain : numpy.ndarray
        Constraint cost Sc: ``M`` per violating segment plus ``violation_slope`` per metre of violation.
    energy : numpy.ndarray
        Energy term Ec in cost units (``energy_j`` or the document's energy times :attr:`CostModel.scale`).
    energy_j : numpy.ndarray
        Physical propulsion and hotel energy (J).
    duration_s : numpy.ndarray
        Travel time (s).
    violations : numpy.ndarray
        Violating segments per path (int).
    min_clearance : numpy.ndarray
        Smallest geometric clearance: altitude above the seabed or distance to a static obstacle (m).
    """

    total: FloatArray
    length: FloatArray
    terrain: FloatArray
    energy: FloatArray
    energy_j: FloatArray
    duration_s: FloatArray
    violations: IntArray
    min_clearance: FloatArray
    """Smallest geometric clearance: altitude above the seabed or distance to a static obstacle (m)."""

    @property
    def feasible(self) -> BoolArray:
        """Where no segment violates a constraint and the current never beats the vehicle.

        Returns
        -------
        numpy.ndarray of bool
            ``(P,)``.
        """
        feasible: BoolArray = self.violations == 0
        return feasible

    def row(self, i: int) -> CostRow:
        """The terms of one path as plain numbers.

        Parameters
        ----------
        i : int
            Path index.

        Returns
        -------
        CostRow
            ``total``, ``length``, ``terrain``, ``energy``, ``energy_j``, ``duration_s``,
            ``violations`` and ``min_clearance_m``.
        """
        return {
            "total": float(self.total[i]),
            "length": float(self.length[i]),
            "terrain": float(self.terrain[i]),
            "energy": float(self.energy[i]),
            "energy_j": float(self.energy_j[i]),
            "duration_s": float(self.duration_s[i]),
            "violations": int(self.violations[i]),
            "min_clearance_m": float(self.min_clearance[i]),
        }


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


def segment_energy(world: World, a: ArrayLike, b: ArrayLike, model: CostModel,
                   current: ArrayLike | None = None) -> tuple[FloatArray, FloatArray, FloatArray, BoolArray]:
    """Energy of straight segments at the vehicle's speed in the current field.

    The current is taken at each segment's midpoint (see the module notes for the two models),
    or given as ``current``.

    Parameters
    ----------
    world : World
        Source of the current field.
    a, b : array_like
        Segment starts and ends ``(..., 3)`` (m); broadcast together.
    model : CostModel
        Speed, power model and energy model.
    current : array_like, optional
        Current per segment ``(..., 3)`` (m/s) instead of the field at the midpoints.

    Returns
    -------
    units : ndarray
        Energy in the model's own units (J for ``"physical"``), before ``model.scale``.
    energy_j, duration_s : ndarray
        Physical energy (J) and travel time (s) of each segment.
    blocked : ndarray of bool
        Where the current beats the vehicle (no ground speed along the segment).
    """
    arrays = [np.asarray(v, dtype=float) for v in ((a, b) if current is None else (a, b, current))]
    if len(arrays) == 2 and arrays[0].shape == arrays[1].shape:  # nothing to broadcast (the elastic band's case)
        lead = arrays[0].shape[:-1]
        a, b, *given = (np.ascontiguousarray(v.reshape(-1, 3)) for v in arrays)
    else:
        lead = np.broadcast_shapes(*(v.shape[:-1] for v in arrays))
        a, b, *given = (np.ascontiguousarray(np.broadcast_to(v, lead + (3,)).reshape(-1, 3)) for v in arrays)
    c = _midpoint_currents(world, a[None], b[None])[0] if current is None else given[0]  # (N, 3) or (1, 3)
    units, energy_j, dt = (np.empty(a.shape[0]) for _ in range(3))
    blocked = np.empty(a.shape[0], dtype=bool)
    _segment_energies(_read_only(a), _read_only(b), _read_only(c), float(model.speed), propulsion_power(model),
                      energy_mode(model), units, energy_j, dt, blocked)
    return units.reshape(lead), energy_j.reshape(lead), dt.reshape(lead), blocked.reshape(lead)


def propulsion_power(model: CostModel) -> float:
    """Electrical power at the model's speed.

    Parameters
    ----------
    model : CostModel
        Speed and power model.

    Returns
    -------
    float
        Hotel load + drag_k · V³ (W).
    """
    return float(model.hotel_power + model.drag_k * model.speed**3)


@kernel
def energy_kernel(ex: float, ey: float, ez: float, ds: float, cx: float, cy: float, cz: float, speed: float,
                  power: float, document: int) -> tuple[float, float, float, bool]:
    """Energy of one segment in a current (compiled; module notes).

    Track tangent ŝ, c∥ = c·ŝ, c⊥² = |c|² - c∥², ground speed c∥ + √(V² - c⊥²), time, energy.

    Parameters
    ----------
    ex, ey, ez : float
        Segment vector (m).
    ds : float
        Its length (m).
    cx, cy, cz : float
        Current on the segment (m/s).
    speed : float
        Through-water speed V (m/s).
    power : float
        Electrical power at that speed (W).
    document : int or bool
        :func:`energy_mode`: 0 (False) joules for ``units``; 1 (True) document 002's energy
        (eqs. 16–17) divided by the current's speed; 2 the same divided by the vehicle's speed V.

    Returns
    -------
    tuple
        ``(units, joules, seconds, blocked)``; blocked where V < c⊥ or the ground speed is not
        positive (the time then assumes the still-water speed).
    """
    c_par = (cx * ex + cy * ey + cz * ez) / ds if ds > 0.0 else 0.0
    c2 = cx * cx + cy * cy + cz * cz
    g = crab_speed(cx, cy, cz, ex / ds, ey / ds, ez / ds, speed, False, 1.0) if ds > 0.0 else c_par + speed
    vg = g if g == g else c_par  # (no heading holds the line: the along-line current alone, as before)
    blocked = not makes_headway(g) and ds > 0.0
    t = ds / (speed if (blocked or vg <= 0.0) else vg) if ds > 0.0 else 0.0
    if document == 2:
        units = abs(vg) ** 3 * ds / speed
    elif document:
        units = abs(vg) ** 3 * ds / max(math.sqrt(c2), 1e-3)
    else:
        units = power * t
    return units, power * t, t, blocked


@kernel
def _segment_energies(a: FloatArray, b: FloatArray, c: FloatArray, speed: float, power: float, document: int,
                      units: FloatArray, energy_j: FloatArray, dt: FloatArray, blocked: BoolArray) -> None:
    for k in range(a.shape[0]):
        ex, ey, ez = b[k, 0] - a[k, 0], b[k, 1] - a[k, 1], b[k, 2] - a[k, 2]
        ds = math.sqrt(ex * ex + ey * ey + ez * ez)
        kc = 0 if c.shape[0] == 1 else k  # (1, 3): one uniform current
        units[k], energy_j[k], dt[k], blocked[k] = energy_kernel(ex, ey, ez, ds, c[kc, 0], c[kc, 1], c[kc, 2],
                                                                  speed, power, document)


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
    if world.obstacles:
        other_slack, other_clear = _obstacle_slack(world, a, b)
    else:
        other_slack = other_clear = np.empty((0, 0))
    if world.zones:  # the exact segment-vs-prism test; a violation as deep as the trace inside a zone
        zone_slack = world.zones.polyline_slack(p)
        if world.obstacles:
            other_slack = np.minimum(other_slack, zone_slack)
        else:
            other_slack, other_clear = zone_slack, np.full(zone_slack.shape, np.inf)
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


def _midpoint_currents(world: World, a: FloatArray, b: FloatArray) -> FloatArray:
    """The current at the midpoints of the segments ``a -> b (P, S - 1, 3)``, or ``(1, 1, 3)`` when the
    field is a :class:`~auvplan.world.UniformCurrent` (the same vector everywhere: no array to fill)."""
    if type(world.currents) is UniformCurrent:
        return np.array(world.currents.vector, dtype=float).reshape(1, 1, 3)
    if jit_enabled() and a.ndim == 3:
        mid = np.empty(a.shape)
        _midpoints(a, b, mid)  # 0.5 (a + b) without numpy's temporaries
    else:
        mid = 0.5 * (a + b)
    current: FloatArray = np.ascontiguousarray(world.currents.velocity(mid))
    return current


@kernel
def _midpoints(a: FloatArray, b: FloatArray, out: FloatArray) -> None:
    for i in range(a.shape[0]):
        for s in range(a.shape[1]):
            for d in range(3):
                out[i, s, d] = 0.5 * (a[i, s, d] + b[i, s, d])


def _read_only(a: FloatArray) -> FloatArray:
    """A read-only view of ``a`` (no copy): a kernel's input typed the same whether or not the caller's array was
    writable, so that it is compiled once."""
    view = a.view()
    view.setflags(write=False)
    return view


def _no_terrain() -> TerrainKernelData:
    """The kernel's terrain argument for a world without a seabed (typed like a real one, never read)."""
    coef = np.zeros((1, 1, 4))
    coef.setflags(write=False)
    return coef, 0.0, 0.0, 1.0, 1.0, 0.0
