"""The convex limits of a waypoint mission: the sea surface, the scenario's depth band and bounds.

The seabed and the obstacles need the legs' exact geometry (:func:`auvplan.guidance.mission.flycheck.fly_check`);
these three limits do not.  Each is convex (a half-space or a box), and under both depth
semantics a vehicle's depth on a leg stays between depths the mission itself names: ``"ramp"``
moves linearly from one end to the other; ``"held"`` lies in the leg's envelope (between its two
end depths), and its executor model changes depth monotonically towards each held depth, so it
never leaves the range of the waypoints' depths.  Hence every leg keeps a limit exactly when its
two ends do, and the waypoints decide: :func:`waypoint_limits` lists the ones that break each.

A QGroundControl ``.plan`` starts from its home, the launch point on the surface above the
first item: the first leg is the descent from the surface, so the depth band applies from the
first mission item on (``launch=True``); the surface and the bounds still apply to the home.
The exemption holds only for a home above the first item (within :data:`LAUNCH_ABOVE_M`): ArduSub
flies the launch leg as a straight line from where the vehicle is to the item's position and depth
(``AC_WPNav::set_wp_destination`` from the stopping point, ``calculate_straight_leg``), so from a home
elsewhere (a plan QGroundControl wrote with the vehicle's own home) the vehicle runs shallower than
``min_depth_m`` over a horizontal stretch: the home is then judged against the band like any waypoint,
and the reason names the launch leg's horizontal run.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TypedDict

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...geometry import as_points
from ...world import Bounds, World

__all__ = ["LAUNCH_ABOVE_M", "WaypointLimits", "WaypointLimitsDict", "waypoint_limits"]

LAUNCH_ABOVE_M = 0.05
"""A launch point at most this far horizontally from the first item is above it (m): four of MAVLink's 1e-7°
position quanta (1.1 cm), so a home written at the item's own latitude and longitude passes whatever rounding."""

_F64 = NDArray[np.float64]
"""Array of float64 (m)."""


class WaypointLimitsDict(TypedDict):
    """JSON form of :class:`WaypointLimits` (lengths in m; waypoint indices from 0).

    Attributes
    ----------
    above_surface, outside_depth_band, outside_bounds : list of int
        The waypoints that break each limit.
    min_depth_m, max_depth_m : float
        The scenario's depth band.
    shallowest_m, deepest_m : float
        The least and greatest waypoint depth (the launch point excluded).
    """

    above_surface: list[int]
    outside_depth_band: list[int]
    outside_bounds: list[int]
    min_depth_m: float
    max_depth_m: float
    shallowest_m: float
    deepest_m: float


@dataclass(frozen=True, eq=False)
class WaypointLimits:
    """Which waypoints of a mission leave the water, the depth band or the scenario's bounds.

    Attributes
    ----------
    waypoints : ndarray (N, 3)
        The mission (local frame, m, z up).
    above_surface : tuple of int
        Waypoints above the sea surface (z > 0).
    outside_depth_band : tuple of int
        Waypoints in the water but shallower than ``min_depth_m`` or deeper than ``max_depth_m``
        (the launch point of a ``.plan`` is exempt).
    outside_bounds : tuple of int
        Waypoints outside the scenario's bounds box (one above the surface counts only when it
        would be outside at the surface, so that each waypoint is named for what it breaks).
    min_depth_m, max_depth_m : float
        The scenario's depth band (m).
    bounds : Bounds
        The scenario's bounds.
    launch : bool
        Whether waypoint 0 is a launch point on the surface above waypoint 1 (exempt from the depth band).
    launch_run_m : float
        A launch point that is not above waypoint 1: the launch leg's horizontal run (m; 0 otherwise).
    """

    waypoints: _F64
    above_surface: tuple[int, ...]
    outside_depth_band: tuple[int, ...]
    outside_bounds: tuple[int, ...]
    min_depth_m: float
    max_depth_m: float
    bounds: Bounds
    launch: bool = False
    launch_run_m: float = 0.0

    @property
    def ok(self) -> bool:
        """True when every waypoint (hence every leg) keeps the three limits."""
        return not (self.above_surface or self.outside_depth_band or self.outside_bounds)

    def depth_range(self) -> tuple[float, float]:
        """Return the least and the greatest depth of the waypoints (the launch point excluded).

        Returns
        -------
        tuple of float
            ``(shallowest, deepest)`` (m, positive down).
        """
        depth = -self.waypoints[int(self.launch):, 2]
        return float(depth.min()), float(depth.max())

    def as_dict(self) -> WaypointLimitsDict:
        """Summarise the limits as plain JSON.

        Returns
        -------
        WaypointLimitsDict
            The offending waypoints per limit, the band and the depth range.
        """
        shallow, deep = self.depth_range()
        return {"above_surface": list(self.above_surface), "outside_depth_band": list(self.outside_depth_band),
                "outside_bounds": list(self.outside_bounds), "min_depth_m": self.min_depth_m,
                "max_depth_m": self.max_depth_m, "shallowest_m": shallow, "deepest_m": deep}

    def reasons(self) -> list[str]:
        """Return one phrase per broken limit, naming its first waypoint.

        Returns
        -------
        list of str
            Empty when :attr:`ok`.
        """
        w, out = self.waypoints, []
        if self.above_surface:
            k = self.above_surface[0]
            out.append(f"{_count(self.above_surface)} above the sea surface (waypoint {k} is {w[k, 2]:.2f} m "
                       f"above it)")
        if self.outside_depth_band:
            k = self.outside_depth_band[0]
            depth = 0.0 - w[k, 2]  # a home at z = 0 reads 0.00, not -0.00
            side = (f"deeper than max_depth_m = {self.max_depth_m:g}" if depth > self.max_depth_m
                    else f"shallower than min_depth_m = {self.min_depth_m:g}")
            run = (f"; the launch point is {self.launch_run_m:.1f} m from above waypoint 1: ArduSub dives the "
                   f"straight launch leg" if k == 0 and self.launch_run_m > 0 else "")
            out.append(f"{_count(self.outside_depth_band)} outside the depth band (waypoint {k} at depth "
                       f"{depth:.2f} m, {side}{run})")
        if self.outside_bounds:
            k = self.outside_bounds[0]
            b = self.bounds
            axes = [f"{name} = {v:.2f} not in [{lo:g}, {hi:g}]"
                    for name, v, lo, hi in zip("xyz", w[k], (b.xmin, b.ymin, b.zmin), (b.xmax, b.ymax, b.zmax))
                    if not lo <= v <= hi]
            out.append(f"{_count(self.outside_bounds)} outside the scenario bounds (waypoint {k}: "
                       f"{', '.join(axes)})")
        return out


def _count(indices: tuple[int, ...]) -> str:
    return f"{len(indices)} waypoint{'s' if len(indices) > 1 else ''}"


def waypoint_limits(world: World, waypoints: ArrayLike, launch: bool = False) -> WaypointLimits:
    """Test every waypoint against the sea surface, the depth band and the bounds of ``world``.

    Parameters
    ----------
    world : World
        Its ``margins`` (``min_depth``, ``max_depth``) and ``bounds``.
    waypoints : array_like
        ``(N, 3)`` mission waypoints (local frame, m, z up).
    launch : bool, optional
        Waypoint 0 is a launch point on the surface (a ``.plan``'s home): exempt from the depth band when it is
        above waypoint 1 (within :data:`LAUNCH_ABOVE_M`; module notes).

    Returns
    -------
    WaypointLimits
        The waypoints that break each limit.
    """
    w = as_points(waypoints).reshape(-1, 3)
    m = world.margins
    depth = -w[:, 2]
    above = w[:, 2] > 0.0
    band = (depth >= m.min_depth) & (depth <= m.max_depth) | above
    run = float(np.hypot(*(w[1, :2] - w[0, :2]))) if launch and w.shape[0] > 1 else 0.0
    launch = launch and run <= LAUNCH_ABOVE_M
    if launch:
        band[:1] = True
    at_most_surface = np.column_stack([w[:, :2], np.minimum(w[:, 2], 0.0)])
    inside = world.bounds.contains(at_most_surface)

    def where(bad: NDArray[np.bool_]) -> tuple[int, ...]:
        return tuple(int(k) for k in np.flatnonzero(bad))

    return WaypointLimits(w.copy(), where(above), where(~band), where(~inside), float(m.min_depth),
                          float(m.max_depth), world.bounds, launch, 0.0 if launch else run)
