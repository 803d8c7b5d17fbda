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
    1 mm/s — and prefers head currents; METHODS.md §2).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .world import World

__all__ = ["CostModel", "CostTerms", "evaluate_paths", "segment_energy"]


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
        ``"physical"`` or ``"document"``.
    w_length, w_terrain, w_energy : float
        Term weights.
    terrain_penalty : float
        M, cost of one violating segment.
    violation_slope : float
        Cost per metre of violation depth.
    energy_scale : float
        Cost units per joule (physical) or per unit of the document's energy; 0 = auto.
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
        if self.energy not in ("physical", "document"):
            raise ValueError(f"energy must be 'physical' or 'document', got {self.energy!r}")

    @property
    def scale(self) -> float:
        """Energy-to-cost conversion in force."""
        if self.energy_scale > 0:
            return self.energy_scale
        if self.energy == "physical":
            return self.speed / (self.hotel_power + self.drag_k * self.speed**3)
        return 1.0 / self.speed**2  # document: |V_h|³/V_oc ~ V² per metre in a 1 m/s current


@dataclass(frozen=True, eq=False)
class CostTerms:
    """Per-path cost terms (arrays of shape ``(P,)``)."""

    total: np.ndarray
    length: np.ndarray
    terrain: np.ndarray
    energy: np.ndarray
    energy_j: np.ndarray
    duration_s: np.ndarray
    violations: np.ndarray
    min_clearance: np.ndarray
    """Smallest geometric clearance: altitude above the seabed or distance to a static obstacle (m)."""

    @property
    def feasible(self) -> np.ndarray:
        """True where no segment violates a constraint and the current never beats the vehicle."""
        return self.violations == 0

    def row(self, i: int) -> dict:
        """The terms of path ``i`` as plain floats."""
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


def _segment_slack(world: World, a: np.ndarray, b: np.ndarray, exact: bool) -> tuple[np.ndarray, np.ndarray]:
    """Minimum slack of every constraint along segments ``a -> b`` (..., 3), and the geometric
    clearance (altitude above the seabed, distance to static obstacles).

    Values below zero are always exact; with ``exact=False`` positive terrain slack may be a
    provable lower bound instead of the exact value.
    """
    m = world.margins
    ends = np.stack([a, b], axis=-2)
    # convex constraints (depth band, bounds): the end points decide
    z = np.stack([a[..., 2], b[..., 2]], axis=-1)
    slack = np.minimum((-z - m.min_depth).min(axis=-1), (m.max_depth + z).min(axis=-1))
    slack = np.minimum(slack, world.bounds.slack(ends).min(axis=-1))
    clearance = np.full(slack.shape, np.inf)
    if world.terrain is not None:
        alt = world.terrain.segment_min_altitude(ends, threshold=np.inf if exact else m.min_altitude)
        clearance = alt
        slack = np.minimum(slack, alt - m.min_altitude)
    for shape in world.obstacles:
        d = np.minimum(shape.distance(a), shape.distance(b))
        touch = shape.segments_hit(ends, 0.0)
        hit = shape.segments_hit(ends, m.obstacle) if m.obstacle > 0 else touch
        clearance = np.minimum(clearance, np.where(touch, np.minimum(d, 0.0), d))
        # a segment can pass through an obstacle with both ends outside: charge at least a metre
        slack = np.minimum(slack, np.where(hit, np.minimum(d - m.obstacle, -1.0), d - m.obstacle))
    return slack, clearance


def segment_energy(world: World, a: np.ndarray, b: np.ndarray, model: CostModel, current=None):
    """Energy of straight segments ``a -> b`` (..., 3) at the vehicle's speed in the current field.

    The current is taken at each segment's midpoint (see the module notes for the two models),
    or given as ``current`` (..., 3).

    Returns
    -------
    units : ndarray
        Energy in the model's own units (J for ``"physical"``), before ``model.scale``.
    energy_j, duration_s : ndarray
        Physical energy (J) and travel time (s) of each segment.
    blocked : ndarray of bool
        Where the current beats the vehicle (no ground speed along the segment).
    """
    d = b - a
    ds = np.linalg.norm(d, axis=-1)
    if current is None:
        mid = 0.5 * (a + b)
        current = world.currents.velocity(mid.reshape(-1, 3)).reshape(mid.shape)
    c = current
    safe_ds = np.where(ds > 0, ds, 1.0)
    s_hat = d / safe_ds[..., None]
    c_par = np.einsum("...i,...i->...", c, s_hat)
    c_perp2 = np.maximum(np.einsum("...i,...i->...", c, c) - c_par**2, 0.0)
    V = model.speed
    disc = V * V - c_perp2
    root = np.sqrt(np.maximum(disc, 0.0))
    vg = c_par + root
    blocked = ((disc < 0) | (vg <= 1e-9)) & (ds > 0)
    vg_safe = np.where(blocked | (vg <= 0), V, vg)
    dt = np.where(ds > 0, ds / vg_safe, 0.0)
    energy_j = (model.hotel_power + model.drag_k * V**3) * dt
    if model.energy == "physical":
        return energy_j, energy_j, dt, blocked
    vh = np.abs(root + c_par)
    voc = np.maximum(np.sqrt(np.einsum("...i,...i->...", c, c)), 1e-3)
    return vh**3 * ds / voc, energy_j, dt, blocked


def evaluate_paths(world: World, points: np.ndarray, model: CostModel, exact: bool = False) -> CostTerms:
    """Cost terms of sampled paths ``points (P, S, 3)`` in ``world`` (static obstacles only).

    Violations are always detected exactly; ``exact=True`` also makes the reported
    ``min_clearance`` exact (otherwise it may be a lower bound where it is large).
    """
    p = np.asarray(points, dtype=float)
    if p.ndim == 2:
        p = p[None]
    a, b = p[:, :-1], p[:, 1:]
    d = b - a
    ds = np.linalg.norm(d, axis=-1)
    length = ds.sum(axis=-1)
    slack, clearance = _segment_slack(world, a, b, exact)
    bad = slack < 0
    depth = np.where(bad, -slack, 0.0)
    energy_units, energy_j, dt, blocked = segment_energy(world, a, b, model)
    energy_j = energy_j.sum(axis=-1)
    duration = dt.sum(axis=-1)
    energy_units = energy_units.sum(axis=-1)
    bad_any = bad | blocked
    violations = bad_any.sum(axis=-1)
    terrain = model.terrain_penalty * violations + model.violation_slope * depth.sum(axis=-1)
    energy = model.scale * energy_units
    total = model.w_length * length + model.w_terrain * terrain + model.w_energy * energy
    return CostTerms(
        total=total,
        length=length,
        terrain=terrain,
        energy=energy,
        energy_j=energy_j,
        duration_s=duration,
        violations=violations,
        min_clearance=clearance.min(axis=-1),
    )
