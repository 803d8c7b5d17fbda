"""A mission's navigation: its fixes planned (or timed), the waypoints that carry them, the predicted
error at every waypoint and leg, and the clearance under that error (issue 52; ``docs/navigation.md``)."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike

from .._types import BoolArray, FloatArray
from ..world import World
from .budget import DEFAULT_STEP_M, NavBudget, mission_budget
from .clearance import uncertain_clearance, zone_within
from .fixes import FixPlan, apply_fixes, best_period, periodic_fixes, plan_fixes, route_profile
from .params import NavParams

__all__ = ["NavCheck", "NavPlan", "check_navigation", "plan_navigation", "surface_kinds", "fix_times",
           "navigation_of", "clearance_failure", "through_water"]


@dataclass(frozen=True, eq=False)
class NavCheck:
    """A mission's predicted error and clearance under it.

    Attributes
    ----------
    budget : NavBudget
        Errors at the waypoints and on the legs.
    leg_uncertain_altitude_m : numpy.ndarray
        ``(N - 1,)`` least altitude above the highest seabed within each leg's error (m; within
        ``max_error_m`` for a leg whose error exceeds it).
    leg_clear : numpy.ndarray of bool
        ``(N - 1,)`` each leg clear of the seabed and the obstacles under its error.
    ok : bool
        Error within ``max_error_m`` everywhere and every leg clear.
    message : str
        The first failure, "" when ok.
    """

    budget: NavBudget
    leg_uncertain_altitude_m: FloatArray
    leg_clear: BoolArray
    ok: bool
    message: str


def check_navigation(world: World, points: ArrayLike, kinds: tuple[str, ...], nav: NavParams,
                     usbl_xy: tuple[float, float] | None = None, step: float = DEFAULT_STEP_M,
                     first_leg: int = 1, held_water_m: ArrayLike | None = None,
                     water_m: ArrayLike | None = None, launch_water_m: float | None = None) -> NavCheck:
    """Predict a mission's error and test its legs under it (what ``mission check`` prints per leg).

    Parameters
    ----------
    world : World
        Seabed, obstacles, margins.
    points : array_like
        ``(N, 3)`` waypoints (m).
    kinds : tuple of str
        ``(N,)`` the fix at each waypoint (``""``, ``"gps"``, ``"usbl"``).
    nav : NavParams
        The error model and the budget.
    usbl_xy : tuple of float, optional
        The USBL ship's local position (m).
    step : float, optional
        Sampling of the altitude schedule and of the clearance test (m).
    first_leg : int, optional
        The number the message gives the first leg (``mission check``: 0, a leg named by the waypoint it leaves).
    held_water_m : array_like, optional
        ``(N,)`` the distance moved through the water while holding at each waypoint (m;
        :func:`~auvplan.nav.budget.hold_drift`): the drift of a hold at depth without bottom lock.
    water_m : array_like, optional
        ``(N - 1,)`` each leg's horizontal distance through the water (m;
        :meth:`auvplan.endurance.Traverse.leg_water_m`): the drift without bottom lock; default: still water.
    launch_water_m : float, optional
        The launch's distance through the water, its dive from the surface above the first waypoint counted in the
        drift (m; :func:`~auvplan.nav.budget.mission_budget`); None: not counted (a file whose legs hold their
        launch, a ``.plan`` read back home first, or one that starts at the first waypoint).

    Returns
    -------
    NavCheck
        The verdict.
    """
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    budget = mission_budget(world, p, kinds, nav, usbl_xy, step, held_water_m, water_m, launch_water_m)
    # a leg over the budget fails on its error; its clearance is tested at the budget (the scan stays bounded)
    pieces = None if budget.piece_error_m is None else np.minimum(budget.piece_error_m, nav.max_error_m)
    alt, clear = uncertain_clearance(world, p, np.minimum(budget.leg_error_m, nav.max_error_m), step, pieces)
    over = np.flatnonzero(budget.leg_error_m > nav.max_error_m * (1.0 + 1e-9))
    msg = ""
    if over.size:
        k = int(over[0])
        msg = (f"leg {k + first_leg}: predicted error {budget.leg_error_m[k]:.1f} m exceeds max_error_m "
               f"{nav.max_error_m:g} m")
    elif not clear.all():
        k = int(np.flatnonzero(~clear)[0])
        msg = clearance_failure(k + first_leg, float(budget.leg_error_m[k]), float(alt[k]), world,
                                np.stack([p[k:k + 1], p[k + 1:k + 2]], axis=1))
    elif budget.error_m[-1] > nav.max_error_m * (1.0 + 1e-9):  # grown in the last waypoint's hold
        msg = (f"waypoint {p.shape[0] - 1}: predicted error {budget.error_m[-1]:.1f} m at the end of its hold "
               f"exceeds max_error_m {nav.max_error_m:g} m")
    return NavCheck(budget, alt, clear, not msg, msg)


def clearance_failure(leg: int, error: float, altitude: float, world: World,
                      segments: ArrayLike | None = None) -> str:
    """Why a leg is not clear under its error: the seabed (its least uncertain altitude under ``min_altitude_m``),
    else a charted no-go zone within the error (:func:`~auvplan.nav.clearance.zone_within`), else a static obstacle
    within its margin plus the error.

    Parameters
    ----------
    leg : int
        The leg's number in the message.
    error : float
        Its predicted error (m).
    altitude : float
        Its least altitude above the seabed within the error (m; ``inf`` without a seabed).
    world : World
        The margins and the zones.
    segments : array_like, optional
        ``(K, 2, 3)`` the leg (or the pieces of its track, m): the zone within the error is named.

    Returns
    -------
    str
        The message.
    """
    head = f"leg {leg}: within its predicted error {error:.1f} m"
    if altitude < world.margins.min_altitude:
        return f"{head} the seabed comes within {altitude:.1f} m (min_altitude_m {world.margins.min_altitude:g} m)"
    if segments is not None and world.zones:
        hit = zone_within(world, segments, error)
        if (hit >= 0).any():
            name = world.zones.exact.zones[int(hit[hit >= 0][0])].name
            return f"{head} the no-go zone {name!r} comes within it (horizontally, at the leg's depth)"
    return f"{head} a static obstacle comes within its margin {world.margins.obstacle:g} m"


@dataclass(frozen=True, eq=False)
class NavPlan:
    """A route with its fixes: the mission flown and its navigation figures.

    Attributes
    ----------
    points : numpy.ndarray
        ``(N, 3)`` the mission's waypoints, surfacings included (m).
    kinds : tuple of str
        ``(N,)`` the fix at each waypoint.
    dwell_s : numpy.ndarray
        ``(N,)`` time held at each waypoint (``surface_s`` at a surfacing; s).
    check : NavCheck
        Predicted error and uncertain clearance of the mission.
    fixes : FixPlan
        The fixes chosen (or timed).
    fixed_period : tuple of (float, FixPlan) or None
        The best fixed period with the same largest error and its fixes (``fixes = "plan"`` only).
    times_s : numpy.ndarray
        ``(F,)`` planned time of each fix (s from the start, earlier dwells included): at the cruise speed in
        still water, or from :attr:`vertex_times_s` once the mission is timed (:meth:`timed`).
    params : NavParams or None
        The error model the figures come from (the error band and the error against time redraw from it).
    speed : float
        The cruise speed the times are planned at (m/s).
    vertex_times_s : numpy.ndarray or None
        ``(N,)`` planned arrival at each waypoint (s) through the World's current at the legs' own speeds
        (:func:`auvplan.sim.navigation.timed_navigation`); None: at the cruise speed in still water.
    leg_water_m : numpy.ndarray or None
        ``(N - 1,)`` each leg's horizontal distance through the water, flown as :attr:`vertex_times_s` (m); the
        budget's drift without bottom lock grows with it (:func:`through_water`); None: still water.
    launch_water_m : float or None
        The launch's distance through the water (its dive from the surface above the first waypoint, flown as a
        ``.plan`` flies it: :func:`auvplan.sim.navigation.timed_navigation`); None: the launch not counted.
    """

    points: FloatArray
    kinds: tuple[str, ...]
    dwell_s: FloatArray
    check: NavCheck
    fixes: FixPlan
    fixed_period: tuple[float, FixPlan] | None
    times_s: FloatArray
    params: NavParams | None = None
    speed: float = math.nan
    vertex_times_s: FloatArray | None = None
    leg_water_m: FloatArray | None = None
    launch_water_m: float | None = None

    def timed(self, vertex_times_s: ArrayLike) -> NavPlan:
        """The same plan with its waypoints' planned arrival times (and so its fixes' times) given.

        Parameters
        ----------
        vertex_times_s : array_like
            ``(N,)`` arrival at each waypoint (s from the start, earlier dwells included).

        Returns
        -------
        NavPlan
            ``times_s`` the arrivals at the fixes.
        """
        t = np.asarray(vertex_times_s, dtype=float).reshape(-1)
        if t.shape != (self.points.shape[0],):
            raise ValueError(f"{t.size} arrival times for {self.points.shape[0]} waypoints")
        return replace(self, times_s=t[[i for i, k in enumerate(self.kinds) if k]], vertex_times_s=t)

    @property
    def ok(self) -> bool:
        """The fixes were found and the mission keeps its budget and clearance."""
        return self.fixes.ok and self.check.ok

    @property
    def message(self) -> str:
        """Why not ok ("" when ok)."""
        return self.fixes.message or self.check.message

    def metrics(self) -> dict[str, float | int | None]:
        """``metrics.json``'s navigation figures.

        Returns
        -------
        dict
            ``nav_error_max_m``, ``fixes``, ``fixes_fixed_period``, ``fixed_period_s``.
        """
        fp = self.fixed_period
        return {"nav_error_max_m": round(self.check.budget.max_error_m, 3),
                "fixes": sum(1 for k in self.kinds if k),
                "fixes_fixed_period": None if fp is None else fp[1].count,
                "fixed_period_s": None if fp is None else round(fp[0], 1)}


def surface_kinds(points: ArrayLike, depth_tol: float = 0.5) -> tuple[str, ...]:
    """The fixes of a mission read back from its waypoints: a waypoint at the surface (depth within
    ``depth_tol``) after the first is a GPS fix.

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` waypoints (m).
    depth_tol : float, optional
        Depth that counts as the surface (m).

    Returns
    -------
    tuple of str
        ``(N,)``.
    """
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    return tuple("gps" if i > 0 and -z <= depth_tol else "" for i, z in enumerate(p[:, 2]))


def fix_times(points: ArrayLike, kinds: tuple[str, ...], dwell_s: ArrayLike, speed: float) -> FloatArray:
    """Planned time of each fix (arrival at its waypoint, earlier dwells included; s).

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` waypoints (m).
    kinds : tuple of str
        ``(N,)`` fixes.
    dwell_s : array_like
        ``(N,)`` dwell at each waypoint (s).
    speed : float
        Cruise speed (m/s).

    Returns
    -------
    numpy.ndarray
        ``(F,)`` one time per fix.
    """
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    t = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))] / speed
    t = t + np.r_[0.0, np.cumsum(np.asarray(dwell_s, dtype=float))[:-1]]
    out: FloatArray = t[[i for i, k in enumerate(kinds) if k]]
    return out


def plan_navigation(world: World, route: ArrayLike, nav: NavParams, max_pitch_deg: float, speed: float,
                    usbl_xy: tuple[float, float] | None = None, step: float = DEFAULT_STEP_M,
                    spacing: float = 250.0, compare: bool = True, water_ratio: ArrayLike | None = None,
                    launch_m: float = 0.0, flight: tuple[ArrayLike, ArrayLike] | None = None) -> NavPlan:
    """Fixes for a route as ``[navigation] fixes`` asks, and the mission that carries them.

    Parameters
    ----------
    world : World
        Seabed, obstacles, margins.
    route : array_like
        ``(N, 3)`` the route's waypoints (m).
    nav : NavParams
        Error model, budget and ``fixes``.
    max_pitch_deg : float
        The vehicle's pitch limit: the climbs and dives of the surfacings (degrees).
    speed : float
        Cruise speed (m/s).
    usbl_xy : tuple of float, optional
        The USBL ship's local position (m).
    step : float, optional
        Sampling (m).
    spacing : float, optional
        Distance between candidate fix points (m).
    compare : bool, optional
        With ``fixes = "plan"``, also find the best fixed period with the same largest error.
    water_ratio : array_like, optional
        ``(N - 1,)`` each route leg's horizontal distance through the water over its horizontal length (the route
        flown through the current, :meth:`auvplan.endurance.Traverse.leg_water_m`): the fixes are planned with the
        drift without lock grown over the water distance; default 1 (still water).  The mission with its fixes
        is checked in still water here; :func:`through_water` checks it as flown.
    launch_m : float, optional
        The drift the launch's dive adds by the route's start (m; :func:`~auvplan.nav.budget.launch_drift`): the
        fixes are planned from it.
    flight : tuple of array_like, optional
        ``(node_s, node_t)`` of the route flown through the current at the cruise speed: the periodic fixes (and the
        best fixed period) are timed in it (:func:`~auvplan.nav.fixes.route_profile`); default: still water.

    Returns
    -------
    NavPlan
        The mission; ``ok`` False with the reason when the budget or the clearance cannot be kept.
    """
    r = np.asarray(route, dtype=float).reshape(-1, 3)
    prof = route_profile(world, r, nav, max_pitch_deg, speed, step, water_ratio, launch_m, flight)
    if nav.fixes == "plan":
        fp = plan_fixes(prof, nav, speed, spacing, usbl_xy)
    elif nav.period_s is not None:
        fp = periodic_fixes(prof, nav, nav.period_s, speed)
    else:
        fp = FixPlan(True, np.empty(0), (), math.nan, 0.0)
    points, kinds = apply_fixes(r, fp.s, fp.kinds, prof.tan_pitch)
    check = check_navigation(world, points, kinds, nav, usbl_xy, step)
    dwell = np.array([nav.surface_s if k == "gps" else 0.0 for k in kinds])
    fixed = None
    if compare and nav.fixes == "plan" and fp.ok:
        fixed = best_period(prof, nav, speed, fp.max_error_m)
    return NavPlan(points, kinds, dwell, check, fp, fixed, fix_times(points, kinds, dwell, speed), nav, speed)


def navigation_of(world: World, points: ArrayLike, kinds: tuple[str, ...], nav: NavParams, speed: float,
                  usbl_xy: tuple[float, float] | None = None, step: float = DEFAULT_STEP_M) -> NavPlan:
    """The navigation of a mission whose fixes are already in it (a results folder read back): its budget,
    clearance and fix times; no fixed period to compare.

    Parameters
    ----------
    world : World
        Seabed, obstacles, margins.
    points : array_like
        ``(N, 3)`` the mission's waypoints, surfacings included (m).
    kinds : tuple of str
        ``(N,)`` the fix at each waypoint.
    nav : NavParams
        Error model and budget.
    speed : float
        Cruise speed (m/s).
    usbl_xy : tuple of float, optional
        The USBL ship's local position (m).
    step : float, optional
        Sampling (m).

    Returns
    -------
    NavPlan
        The mission's navigation.
    """
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    check = check_navigation(world, p, kinds, nav, usbl_xy, step)
    dwell = np.array([nav.surface_s if k == "gps" else 0.0 for k in kinds])
    s = np.r_[0.0, np.cumsum(np.hypot(*np.diff(p[:, :2], axis=0).T))]
    idx = [i for i, k in enumerate(kinds) if k]
    fp = FixPlan(True, s[idx], tuple(kinds[i] for i in idx), check.budget.max_error_m,
                 float(dwell.sum()))
    return NavPlan(p, tuple(kinds), dwell, check, fp, None, fix_times(p, kinds, dwell, speed), nav, speed)


def through_water(world: World, plan: NavPlan, water_m: ArrayLike, step: float = DEFAULT_STEP_M,
                  launch_water_m: float | None = None) -> NavPlan:
    """The plan's budget and clearance checked again with each leg's drift without bottom lock grown over its
    distance through the water (``docs/navigation.md``).

    Parameters
    ----------
    world : World
        Seabed, obstacles, margins.
    plan : NavPlan
        The mission and its error model (``params``).
    water_m : array_like
        ``(N - 1,)`` each leg's horizontal distance through the water (m;
        :meth:`auvplan.endurance.Traverse.leg_water_m`).
    step : float, optional
        Sampling (m).
    launch_water_m : float, optional
        The launch's distance through the water (m): its dive counted in the drift (:func:`check_navigation`).

    Returns
    -------
    NavPlan
        ``check``, ``leg_water_m`` and ``launch_water_m`` replaced; ``plan`` itself without an error model.
    """
    if plan.params is None:
        return plan
    w = np.asarray(water_m, dtype=float).reshape(-1)
    nav = plan.params
    check = check_navigation(world, plan.points, plan.kinds, nav, nav.usbl_xy, step, water_m=w,
                             launch_water_m=launch_water_m)
    return replace(plan, check=check, leg_water_m=w, launch_water_m=launch_water_m)
