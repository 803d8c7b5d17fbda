"""Hybrid potential-field path tracking for a single-rudder vehicle (document 001).

Wang et al. 2020, Ship Science and Technology 42(12); docs/methods.md §3.  One commanded direction
from three fields, for the active leg A → B with unit direction t̂ and right normal n̂:

* route attraction (eq. 3): magnitude k_H·|e| perpendicular to the leg, towards it
  (e the cross-track error);
* heading attraction (eq. 4): magnitude k_X·Δ along the leg;
  together (eqs. 5–6) χ = ψ_leg + atan2(−k_H e, k_X Δ) — LOS in potential-field form;
* obstacle repulsion (eqs. 7–8, the improved field with a goal-distance factor): for an obstacle
  whose surface is r_re < P_o away, F_rep = m_r (1/r_re − 1/P_o) (1/r_re²) ρ pointing from the
  obstacle to the vehicle, with the goal-distance factor ρ of r_at, the distance to the active
  waypoint (:func:`goal_factor`).

The resultant is the commanded direction.  Two variants (``HybridParams.variant``):

``"document"`` — the field of eqs. 3–8 as written: ρ = (r_at / P_o)^n, uncapped.  Eq. 8 writes
    m·r_at^n; ``k_repulse`` = m·P_o^n only sets the gain's units, so that ρ = 1 at r_at = P_o.  The
    factor grows with the distance to the target (ρ = 12 on a 600 m leg's midpoint with P_o = 25 m)
    and vanishes at the target.  No lateral bias and no current compensation by default: the
    resultant is flown as a heading.
``"corrected"`` (default) — three engineering additions, each switchable:
    (1) ρ = min(r_at / P_o, 1)^n: the factor only fades the repulsion within P_o of the target
    (so a waypoint next to an obstacle stays reachable) and leaves its scale independent of the
    leg's length; (2) a lateral bias ``lateral_bias``·|F_rep| along the leg normal, away from the
    side of the route the obstacle sits on (starboard for an obstacle on the route), which breaks
    the head-on symmetry where repulsion and attraction are collinear and would deadlock; two
    obstacles straddling the route cancel their biases, so the vehicle passes between them;
    (3) the resultant is a course over ground, turned into a heading with the measured current
    (crab angle β = asin(c⊥ / u), :func:`crab_heading`), as a DVL/ADCP-equipped vehicle does.

``lateral_bias`` and ``current_compensation`` left unset take the variant's choice; set, they
apply to either variant (LOS and ILOS take the same ``current_compensation``, so the laws can be
compared with and without it).  With no obstacle within P_o, k_H = k_X and the same compensation,
the field commands exactly LOS's heading (:func:`auvplan.guidance.following.los.los_heading`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .route import RoutePoint, RouteTracker, crab_heading

__all__ = ["VARIANTS", "HybridParams", "goal_factor", "hybrid_force", "crab_heading", "HybridGuidance"]

VARIANTS = ("corrected", "document")
"""The field's variants: the corrected default and document 001's eqs. 3–8 as written."""


@dataclass(frozen=True)
class HybridParams:
    """Gains of document 001's hybrid field.

    Attributes
    ----------
    k_route : float
        Route (cross-track) attraction gain k_H.
    k_heading : float
        Heading attraction gain k_X; the heading attraction is k_X·Δ.
    lookahead : float
        Δ (m), along-leg distance of the heading attraction.
    influence : float
        P_o (m), obstacle influence distance from the obstacle surface.
    k_repulse : float
        m_r, repulsion gain (eq. 8's gain m times P_o^n: the factor is normalised by P_o).
    goal_power : float
        n, exponent of the goal-distance factor.
    lateral_bias : float, optional
        Lateral push as a fraction of the repulsion magnitude (0 disables); omitted: 2 for the
        corrected variant, 0 for the document's.
    current_compensation : bool, optional
        Turn the commanded course into a heading with the measured current (crab angle); omitted:
        true for the corrected variant, false for the document's.
    switch_radius : float
        Leg switching radius (m).
    push_bound_m : float
        The most a static obstacle that a clear route passes may shift the line the field steers to (m;
        issue 57): the repulsion of such an obstacle (bias included) acts only across the leg and is
        clipped to ``k_route * push_bound_m``, so the field flies LOS towards a line at most this far off
        the route (:func:`hybrid_force`).  Obstacles the route runs into and moving ones keep the full field.
    variant : str
        "corrected" (goal-distance factor capped at 1, lateral bias, crab angle) or "document"
        (document 001's eqs. 7–8 as written: the factor uncapped, no bias, no crab angle).
    """

    k_route: float = 1.0
    k_heading: float = 1.0
    lookahead: float = 15.0
    influence: float = 25.0
    k_repulse: float = 2.0e4
    goal_power: float = 1.0
    lateral_bias: float | None = None
    current_compensation: bool | None = None
    switch_radius: float = 10.0
    push_bound_m: float = 0.25
    variant: str = "corrected"

    def __post_init__(self) -> None:
        if self.variant not in VARIANTS:
            raise ValueError(f"variant = {self.variant!r}: choose 'corrected' or 'document'")
        for k in ("k_route", "k_heading", "lookahead", "influence", "switch_radius"):
            if not getattr(self, k) > 0:
                raise ValueError(f"{k} = {getattr(self, k)}: must be positive")
        if self.k_repulse < 0 or self.goal_power < 0 or self.bias < 0 or self.push_bound_m < 0:
            raise ValueError("k_repulse, goal_power, lateral_bias and push_bound_m must be >= 0")

    @property
    def bias(self) -> float:
        """The lateral bias in effect (``lateral_bias``, or the variant's: corrected 2, document 0)."""
        if self.lateral_bias is not None:
            return float(self.lateral_bias)
        return 2.0 if self.variant == "corrected" else 0.0

    @property
    def compensates(self) -> bool:
        """Whether the course is turned into a heading with the current (``current_compensation``,
        or the variant's: corrected yes, document no)."""
        if self.current_compensation is not None:
            return bool(self.current_compensation)
        return self.variant == "corrected"

    @property
    def push(self) -> float:
        """The stated push bound (m): the most the field leaves a clear route beyond what LOS does."""
        return float(self.push_bound_m)


def goal_factor(target_distance: float, params: HybridParams) -> float:
    """Goal-distance factor ρ of the repulsion (document 001, eqs. 7–8).

    Parameters
    ----------
    target_distance : float
        r_at, distance from the vehicle to the attraction target (the active waypoint), m.
    params : HybridParams
        ``influence`` P_o, ``goal_power`` n and ``variant``.

    Returns
    -------
    float
        ``"document"``: (r_at / P_o)^n, eq. 8's r_at^n with the gain m = m_r P_o^(−n) — uncapped;
        ``"corrected"``: min(r_at / P_o, 1)^n.
    """
    ratio = target_distance / params.influence
    if params.variant == "corrected":
        ratio = min(ratio, 1.0)
    return float(ratio ** params.goal_power)


def hybrid_force(course: float, cross: float, params: HybridParams, x: float, y: float,
                 obstacles: Sequence[Sequence[float]], target_distance: float,
                 leg_origin: Sequence[float] | NDArray[np.float64],
                 reach: Sequence[float] | None = None,
                 capped: Sequence[bool] | None = None) -> tuple[float, float]:
    """Compute the resultant of route attraction, heading attraction and obstacle repulsion.

    Parameters
    ----------
    course : float
        Compass course of the active leg (rad).
    cross : float
        Cross-track error e, positive to starboard (m).
    params : HybridParams
        The field's gains.
    x, y : float
        Vehicle position east and north (m).
    obstacles : sequence of (float, float, float)
        ``(cx, cy, surface_distance)`` of each obstacle (m).
    target_distance : float
        Horizontal distance to the active waypoint r_at (m).
    leg_origin : sequence of float
        ``(x, y)`` of the active leg's start (m), to tell which side of the route an obstacle is on.
    reach : sequence of float, optional
        Each obstacle's influence distance (m; default ``params.influence`` for all): where the route
        itself passes closer than P_o to a static obstacle, :class:`HybridGuidance` repels only inside
        the route's own clearance (the plan is clear; the field corrects a drift towards the obstacle).
    capped : sequence of bool, optional
        Obstacles whose push is bounded (static obstacles a clear route passes): their repulsion and bias
        are summed, only the part across the leg is kept, clipped to ``k_route * push_bound_m`` — the
        field then steers to a line at most ``push_bound_m`` off the route.

    Returns
    -------
    tuple of float
        The resultant's east and north components (the field's units; only its direction is used).

    Notes
    -----
    Route and heading attraction: eqs. 3–6; repulsion: eqs. 7–8 with :func:`goal_factor`; the
    lateral bias (``params.bias``) is not the document's.
    """
    s, c = math.sin(course), math.cos(course)
    nx, ny = c, -s           # right normal
    fx, fy = _attraction(s, c, cross, params)
    fx, fy, across = _repulsion(fx, fy, params, x, y, obstacles, goal_factor(target_distance, params), nx, ny,
                                leg_origin, reach, capped)
    if across:
        cap = params.k_route * params.push
        across = max(-cap, min(cap, across))
        fx += across * nx
        fy += across * ny
    return fx, fy


def _attraction(s: float, c: float, cross: float, params: HybridParams) -> tuple[float, float]:
    """Heading and route attraction (eqs. 3–6) on a leg of course sine ``s``, cosine ``c``."""
    tx, ty = s, c            # along the leg
    nx, ny = c, -s           # right normal
    fa = params.k_heading * params.lookahead
    fh = -params.k_route * cross
    fx = fa * tx + fh * nx
    fy = fa * ty + fh * ny
    return fx, fy


def _repulsion(fx: float, fy: float, params: HybridParams, x: float, y: float,
               obstacles: Sequence[Sequence[float]], rho: float, nx: float, ny: float,
               leg_origin: Sequence[float] | NDArray[np.float64], reach: Sequence[float] | None,
               capped: Sequence[bool] | None) -> tuple[float, float, float]:
    """``(fx, fy)`` with each obstacle's repulsion (eqs. 7–8, scaled by the goal factor ``rho``, and the lateral
    bias) added in turn, and the capped obstacles' push across the leg (normal ``(nx, ny)``), summed apart."""
    po = params.influence
    bias = params.bias
    across = 0.0  # the bounded obstacles' push across the leg
    for i, (cx, cy, d) in enumerate(obstacles):
        pi = po if reach is None else reach[i]
        if d >= pi:
            continue
        d = max(d, 1e-3)
        mag = params.k_repulse * (1.0 / d - 1.0 / pi) / (d * d) * rho
        rx, ry = x - cx, y - cy
        rn = math.hypot(rx, ry) or 1.0
        gx, gy = mag * rx / rn, mag * ry / rn
        if bias:
            side = (cx - leg_origin[0]) * nx + (cy - leg_origin[1]) * ny
            push = -1.0 if side > 0.5 else 1.0  # away from the obstacle's side; starboard if on the route
            gx += push * bias * mag * nx
            gy += push * bias * mag * ny
        if capped is not None and capped[i]:
            across += gx * nx + gy * ny
        else:
            fx += gx
            fy += gy
    return fx, fy, across

class HybridGuidance:
    """Document 001's guidance along a route (``reset()`` to restart).

    Parameters
    ----------
    route : RouteTracker
        The route to follow.
    params : HybridParams
        The field's gains.
    statics : sequence of shapes, optional
        The world's static obstacles: the field repels from one that the route passes (without entering
        it) closer than P_o only inside the route's own clearance from it (:meth:`_reach`).
    """

    name = "hybrid"

    def __init__(self, route: RouteTracker, params: HybridParams, statics: Sequence[Any] = ()) -> None:
        self.route = route
        self.params = params
        w = np.asarray(route.w, dtype=float)
        legs = np.stack([w[:-1], w[1:]], axis=1)  # an obstacle the route runs into keeps the full field
        self._statics = {(float(o.center[0]), float(o.center[1])): o for o in statics
                         if not bool(np.any(o.segments_hit(legs)))}
        self._a, self._d = w[:-1], np.diff(w, axis=0)
        self._dd = np.maximum((self._d[:, :2] ** 2).sum(axis=1), 1e-12)

    def _reach(self, x: float, y: float, obstacles: Sequence[Sequence[float]]) -> tuple[list[float] | None,
                                                                                       list[bool] | None]:
        """Each obstacle's influence distance: P_o, or the route's own clearance from a static obstacle where
        that is below P_o: the exact surface distance of the route point nearest the vehicle (in plan view;
        at the route's depth there).  An obstacle the route runs into (exact segment test) keeps P_o.  Second:
        which obstacles' push is bounded (``push_bound_m``): the static ones the route passes clear of."""
        if not self._statics or not obstacles:
            return None, None
        po = self.params.influence
        s = np.clip(((x - self._a[:, 0]) * self._d[:, 0] + (y - self._a[:, 1]) * self._d[:, 1]) / self._dd, 0.0, 1.0)
        q = self._a + s[:, None] * self._d
        pt = q[int(np.argmin((q[:, 0] - x) ** 2 + (q[:, 1] - y) ** 2))][None]
        reach, capped = [], []
        for ob in obstacles:
            shape = self._statics.get((float(ob[0]), float(ob[1])))
            clear = float(shape.distance(pt)[0]) if shape is not None else po
            reach.append(clear if 0.0 < clear < po else po)
            capped.append(shape is not None)
        return reach, capped

    def reset(self) -> None:
        """Restart the route."""
        self.route.reset()

    def command(self, x: float, y: float, z: float, current: Sequence[float] | NDArray[np.float64], speed: float,
                obstacles: Sequence[Sequence[float]], dt: float) -> tuple[float, bool, RoutePoint]:
        """Compute the heading command for one step.

        The field's course is converted into a heading with the current when ``params.compensates``.

        Parameters
        ----------
        x, y, z : float
            Vehicle position (m).
        current : sequence of float
            Current at the vehicle, east, north, up (m/s).
        speed : float
            Speed through the water (m/s).
        obstacles : sequence of (float, float, float)
            ``(cx, cy, surface_distance)`` of the nearby obstacles (m).
        dt : float
            Time step (s); unused (the field has no state).

        Returns
        -------
        command : float
            Commanded compass heading (rad).
        is_heading : bool
            Always True.
        point : RoutePoint
            The vehicle's position relative to the route.
        """
        rp = self.route.update(x, y)
        k = rp.leg
        b = self.route.w[k + 1]
        target = math.hypot(b[0] - x, b[1] - y)
        reach, capped = self._reach(x, y, obstacles)
        fx, fy = hybrid_force(rp.course, rp.cross, self.params, x, y, obstacles, target, self.route.w[k], reach, capped)
        course = math.atan2(fx, fy)
        psi = crab_heading(course, current, speed, self.route.tail[k]) if self.params.compensates else course
        return psi, True, rp
