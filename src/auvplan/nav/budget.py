"""The navigation error budget along a mission (issue 52; ``docs/navigation.md``).

Model.  Dead reckoning makes the horizontal position error σ (1σ, radial RMS) grow linearly with the
horizontal distance travelled: by ``drift_pct / 100`` per metre where the DVL has bottom lock (the
altitude, from the mission's depth schedule over the World's seabed, is at most ``dvl_range_m``: the DVL
measures the velocity over the ground, so that error is a share of the ground distance) and by
``drift_pct_no_lock / 100`` per metre travelled **through the water** where it has not (water track: the
current is the unknown).  A leg's horizontal water distance ``W`` comes from flying it through the World's
current at its speed (:meth:`auvplan.endurance.Traverse.leg_water_m`); its no-lock intervals count
``Δs · W / h`` (``h`` the leg's horizontal length; in still water ``W = h``, against a steady head current
``c`` on a level leg ``W = h · V / (V − c)``).  Legs are sampled every ``step`` metres and each
interval is split where the (linearly interpolated) altitude crosses ``dvl_range_m``, so

    D(s) = Σ rate_k · Δs_k   (summed since the last fix),

and the drift adds to the error of the last fix in quadrature (the two are independent):

    σ(s) = sqrt(σ_fix² + D(s)²),     reported error = confidence × σ.

A GPS fix at the surface sets ``σ_fix = fix_error_m`` and ``D = 0``; a USBL fix sets
``σ_fix = error_pct / 100 × slant range``; the mission starts with a fix (``fix_error_m``).

A hold at a waypoint at depth (a ``.plan``'s waypoint or timed loiter holding the item against the current) keeps
the vehicle still over the ground but moves it through the water by ``w = ∫|c| dt``.  With bottom lock the DVL
measures the ground velocity (zero): D does not grow.  Without it the vehicle dead-reckons on water track, whose
error is ``drift_pct_no_lock`` per metre through the water: D grows by ``w · drift_pct_no_lock / 100`` during the
hold, counted before the leg that leaves the waypoint (at the last waypoint, in its error after the hold).  A hold
at a fix (the surface) adds nothing.

The launch.  The vehicle starts at the surface above the mission's first waypoint (its GPS fix there) and dives to
it, as a ``.plan`` flies its launch from its home: a vertical leg from :func:`launch_point`, flown at
:data:`LAUNCH_DIVE_MPS` through the current, that moves the vehicle ``w0`` through the water while it holds its
position.  Given ``launch_water_m = w0``, the budget is that of the mission with the launch as its first leg (the
same samples, lock shares and increments as ``mission check`` computes on the ``.plan`` read back, home first), its
figures given for the mission's own waypoints and legs: the launch's drift is counted in ``D``, the fix's error
``σ_fix`` is the surface's.  :func:`launch_drift` is that ``D`` at the first waypoint, where the fix planner starts.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._types import FloatArray, IntArray
from ..world import World
from .params import NavParams

__all__ = ["NavBudget", "ErrorProfile", "sample_route", "lock_fraction", "drift_increments", "sigma_profile",
           "fix_sigma", "hold_drift", "mission_budget", "error_profile", "water_lengths", "DEFAULT_STEP_M",
           "LAUNCH_DIVE_MPS", "launch_point", "launch_drift"]

DEFAULT_STEP_M = 50.0
"""Longest horizontal sampling interval of the altitude schedule (m)."""

LAUNCH_DIVE_MPS = 1.5
"""The launch's descent speed through the water (m/s): a ``.plan``'s launch from its home, a vertical leg, is flown
at AC_WPNav's default ``WPNAV_SPEED_DN`` (150 cm/s; :mod:`auvplan.io.missions.readback.speeds`), which the file
cannot set."""


@dataclass(frozen=True, eq=False)
class NavBudget:
    """The predicted error of a mission at its waypoints and on its legs.

    Attributes
    ----------
    error_m : numpy.ndarray
        ``(N,)`` confidence × σ at each waypoint, after any fix there (m): ``mission.csv`` ``nav_error_m``.
    leg_error_m : numpy.ndarray
        ``(N - 1,)`` the largest confidence × σ on each leg (at its end, before a fix there; m).
    leg_lock : numpy.ndarray
        ``(N - 1,)`` share of each leg's horizontal length flown with bottom lock.
    kinds : tuple of str
        ``(N,)`` the fix at each waypoint: ``""``, ``"gps"`` or ``"usbl"``.
    max_error_m : float
        The largest error anywhere (m).
    piece_error_m : numpy.ndarray or None
        ``(K,)`` confidence × σ at the end of each piece of the legs (before a fix there; m): the pieces of
        :func:`auvplan.nav.clearance.pieces` at the budget's ``step``, its sampling intervals; σ grows along a piece, so
        this is its largest.  None where not computed.
    """

    error_m: FloatArray
    leg_error_m: FloatArray
    leg_lock: FloatArray
    kinds: tuple[str, ...]
    max_error_m: float
    piece_error_m: FloatArray | None = None


@dataclass(frozen=True, eq=False)
class ErrorProfile:
    """The predicted error along a mission at every sample of its altitude schedule (for the error band
    and the error against time).

    Attributes
    ----------
    xyz : numpy.ndarray
        ``(M, 3)`` the samples (m).
    s_m : numpy.ndarray
        ``(M,)`` distance travelled (3D) from the start (m).
    before_m, after_m : numpy.ndarray
        ``(M,)`` confidence × σ on arrival at each sample and after any fix there (m).
    fix : numpy.ndarray of bool
        ``(M,)`` a fix is taken at the sample.
    """

    xyz: FloatArray
    s_m: FloatArray
    before_m: FloatArray
    after_m: FloatArray
    fix: NDArray[np.bool_]


def sample_route(world: World, points: ArrayLike, step: float = DEFAULT_STEP_M) -> tuple[FloatArray, FloatArray,
                                                                                         IntArray, IntArray]:
    """Sample a polyline's legs every ``step`` metres horizontally (the altitude schedule).

    Parameters
    ----------
    world : World
        The seabed (altitude ``+inf`` without one).
    points : array_like
        ``(N, 3)`` waypoints (m).
    step : float
        Longest horizontal interval (m).

    Returns
    -------
    ds : numpy.ndarray
        ``(M - 1,)`` horizontal length of each interval (m).
    alt : numpy.ndarray
        ``(M,)`` altitude above the seabed at each sample (m).
    leg : numpy.ndarray of int
        ``(M - 1,)`` the leg of each interval.
    vertex : numpy.ndarray of int
        ``(N,)`` the sample index of each waypoint.
    """
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    h = np.hypot(*np.diff(p[:, :2], axis=0).T)
    n = np.maximum(np.ceil(h / step), 1).astype(np.intp)
    leg = np.repeat(np.arange(n.size), n)
    k = np.arange(leg.size) - np.repeat(np.cumsum(n) - n, n)
    f = (k / n[leg])[:, None]
    samples = np.vstack([p[leg] + f * (p[leg + 1] - p[leg]), p[-1:]])
    alt = world.terrain.altitude(samples) if world.terrain is not None else np.full(len(samples), np.inf)
    vertex = np.r_[0, np.cumsum(n)].astype(np.intp)
    return (h / n)[leg], np.asarray(alt, dtype=float), leg.astype(np.intp), vertex


def lock_fraction(alt: ArrayLike, dvl_range: float) -> FloatArray:
    """Share of each interval with bottom lock, the altitude linear between its ends.

    Parameters
    ----------
    alt : array_like
        ``(M,)`` altitudes at the samples (m).
    dvl_range : float
        Bottom lock at altitudes ≤ this (m).

    Returns
    -------
    numpy.ndarray
        ``(M - 1,)`` in ``[0, 1]``: 1 or 0 when both ends agree, else the share on the lock side of the crossing.
    """
    a = np.asarray(alt, dtype=float)
    a0, a1 = a[:-1], a[1:]
    l0, l1 = a0 <= dvl_range, a1 <= dvl_range
    with np.errstate(divide="ignore", invalid="ignore"):
        c = np.clip((dvl_range - a0) / (a1 - a0), 0.0, 1.0)  # where the altitude reaches dvl_range
    return np.where(l0 == l1, l0.astype(float), np.where(l0, c, 1.0 - c))


def drift_increments(ds: ArrayLike, lock: ArrayLike, nav: NavParams, ds_water: ArrayLike | None = None) -> FloatArray:
    """The growth of σ over each interval: ``(f · Δs · drift_pct + (1 − f) · Δw · drift_pct_no_lock) / 100``.

    Parameters
    ----------
    ds : array_like
        ``(M - 1,)`` horizontal lengths over the ground (m).
    lock : array_like
        ``(M - 1,)`` lock shares (:func:`lock_fraction`).
    nav : NavParams
        The rates.
    ds_water : array_like, optional
        ``(M - 1,)`` horizontal lengths through the water (m; :func:`water_lengths`); default ``ds`` (still water).

    Returns
    -------
    numpy.ndarray
        ``(M - 1,)`` (m).
    """
    f = np.asarray(lock, dtype=float)
    g = np.asarray(ds, dtype=float)
    w = g if ds_water is None else np.asarray(ds_water, dtype=float)
    out: FloatArray = g * f * nav.rate(True) + w * (1.0 - f) * nav.rate(False)
    return out


def water_lengths(ds: ArrayLike, leg: ArrayLike, water_m: ArrayLike | None) -> FloatArray | None:
    """Each interval's horizontal length through the water: its leg's water distance ``W`` shared in proportion
    to the intervals' ground lengths (a vertical leg's, ``h = 0``, in equal parts).

    Parameters
    ----------
    ds : array_like
        ``(M - 1,)`` horizontal ground lengths (m).
    leg : array_like of int
        ``(M - 1,)`` the leg of each interval.
    water_m : array_like or None
        ``(L,)`` each leg's horizontal distance through the water (m); None: still water.

    Returns
    -------
    numpy.ndarray or None
        ``(M - 1,)`` (m); None for still water.
    """
    if water_m is None:
        return None
    g = np.asarray(ds, dtype=float)
    k = np.asarray(leg, dtype=np.intp)
    w = np.asarray(water_m, dtype=float).reshape(-1)
    if not np.all(np.isfinite(w)) or w.size <= int(k.max(initial=-1)):
        raise ValueError(f"{w.size} water distances for {int(k.max(initial=-1)) + 1} legs (finite, one per leg)")
    h = np.bincount(k, g, w.size)
    n = np.bincount(k, minlength=w.size)
    out: FloatArray = np.where(h[k] > 0.0, g * w[k] / np.where(h[k] > 0.0, h[k], 1.0), w[k] / np.maximum(n[k], 1))
    return out


def sigma_profile(inc: ArrayLike, resets: ArrayLike, sigma_fix: ArrayLike, sigma0: float) -> tuple[FloatArray,
                                                                                                    FloatArray]:
    """The σ at every sample, before and after any fix there.

    Parameters
    ----------
    inc : array_like
        ``(M - 1,)`` drift increments (:func:`drift_increments`, m).
    resets : array_like of int
        Sample indices where a fix is taken.
    sigma_fix : array_like
        σ right after each of those fixes (m).
    sigma0 : float
        σ at the first sample (the launch fix, m).

    Returns
    -------
    before, after : numpy.ndarray
        ``(M,)`` σ on arrival at each sample and after any fix there (m).
    """
    d = np.r_[0.0, np.cumsum(np.asarray(inc, dtype=float))]
    r = np.asarray(resets, dtype=np.intp).reshape(-1)
    order = np.argsort(r, kind="stable")
    r = r[order]
    base = np.r_[0.0, d[r]]  # D at the start and at each fix
    sfix = np.r_[float(sigma0), np.asarray(sigma_fix, dtype=float).reshape(-1)[order]]
    idx = np.arange(d.size)
    at_or_before = np.searchsorted(r, idx, side="right")  # the last fix at or before each sample (0: start)
    strictly_before = np.searchsorted(r, idx, side="left")
    after = np.hypot(sfix[at_or_before], d - base[at_or_before])
    before = np.hypot(sfix[strictly_before], d - base[strictly_before])
    return before, after


def hold_drift(alt: ArrayLike, kinds: tuple[str, ...], nav: NavParams,
               held_water_m: ArrayLike | None) -> FloatArray:
    """The growth of D while holding at each waypoint (module notes): ``w · drift_pct_no_lock / 100`` without
    bottom lock at a waypoint that is not a fix, else 0.

    Parameters
    ----------
    alt : array_like
        ``(N,)`` the altitude at each waypoint (m).
    kinds : tuple of str
        ``(N,)`` the fix at each waypoint.
    nav : NavParams
        ``dvl_range_m`` and the rate without lock.
    held_water_m : array_like or None
        ``(N,)`` the distance moved through the water while holding at each waypoint (m); None: no hold.

    Returns
    -------
    numpy.ndarray
        ``(N,)`` (m).
    """
    a = np.asarray(alt, dtype=float)
    if held_water_m is None:
        return np.zeros(a.shape)
    w = np.asarray(held_water_m, dtype=float).reshape(a.shape)
    out: FloatArray = np.where((a > nav.dvl_range_m) & ~np.array([bool(k) for k in kinds]), w * nav.rate(False), 0.0)
    return out


def fix_sigma(nav: NavParams, kind: str, point: ArrayLike, usbl_xy: tuple[float, float] | None) -> float:
    """The σ right after a fix of ``kind`` at ``point``.

    Parameters
    ----------
    nav : NavParams
        ``fix_error_m`` and ``usbl``.
    kind : {'gps', 'usbl'}
        The fix.
    point : array_like
        ``(3,)`` where it is taken (m).
    usbl_xy : tuple of float or None
        The USBL ship's local position (m), for ``usbl``.

    Returns
    -------
    float
        σ (m).
    """
    if kind == "usbl":
        if nav.usbl is None or usbl_xy is None:
            raise ValueError("a USBL fix needs [navigation] usbl")
        p = np.asarray(point, dtype=float)
        slant = float(np.sqrt((p[0] - usbl_xy[0]) ** 2 + (p[1] - usbl_xy[1]) ** 2 + p[2] ** 2))
        return nav.usbl.error_pct / 100.0 * slant
    return nav.fix_error_m


def launch_point(points: ArrayLike) -> FloatArray:
    """The launch: the surface above the mission's first waypoint (a ``.plan``'s home).

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` waypoints (m), N ≥ 1.

    Returns
    -------
    numpy.ndarray
        ``(3,)`` (m).
    """
    home: FloatArray = np.asarray(points, dtype=float).reshape(-1, 3)[0].copy()
    home[2] = 0.0
    return home


def _launched(p: FloatArray, kinds: tuple[str, ...], held_water_m: ArrayLike | None, water_m: ArrayLike | None,
              launch_water_m: float) -> tuple[FloatArray, tuple[str, ...], FloatArray, FloatArray]:
    """The mission with its launch as the first leg (module notes): waypoints, fixes, holds, water distances."""
    h = np.hypot(*np.diff(p[:, :2], axis=0).T)
    water = h if water_m is None else np.asarray(water_m, dtype=float).reshape(-1)
    held = np.zeros(p.shape[0]) if held_water_m is None else np.asarray(held_water_m, dtype=float).reshape(-1)
    return (np.vstack([launch_point(p), p]), ("", *kinds), np.r_[0.0, held],
            np.r_[float(launch_water_m), water])


def launch_drift(world: World, start: ArrayLike, nav: NavParams, launch_water_m: float,
                 step: float = DEFAULT_STEP_M) -> float:
    """The drift ``D`` the launch's dive adds by the mission's first waypoint (module notes): the increment the
    budget of the mission launched from :func:`launch_point` counts over its first leg.

    Parameters
    ----------
    world : World
        The seabed (the lock at the surface and at the start).
    start : array_like
        ``(3,)`` the mission's first waypoint (m).
    nav : NavParams
        The rates.
    launch_water_m : float
        The distance the dive moves through the water (m).
    step : float, optional
        Sampling (m).

    Returns
    -------
    float
        ``D`` (m): ``(1 − f) · w0 · drift_pct_no_lock / 100``, ``f`` the dive's share with lock.
    """
    p = np.asarray(start, dtype=float).reshape(1, 3)
    p = np.vstack([launch_point(p), p])
    ds, alt, leg, _ = sample_route(world, p, step)
    return float(drift_increments(ds, lock_fraction(alt, nav.dvl_range_m), nav,
                                  water_lengths(ds, leg, [float(launch_water_m)])).sum())


def mission_budget(world: World, points: ArrayLike, kinds: tuple[str, ...], nav: NavParams,
                   usbl_xy: tuple[float, float] | None = None, step: float = DEFAULT_STEP_M,
                   held_water_m: ArrayLike | None = None, water_m: ArrayLike | None = None,
                   launch_water_m: float | None = None) -> NavBudget:
    """The predicted error along a mission whose fixes are known (:class:`NavBudget`).

    Parameters
    ----------
    world : World
        The seabed (the lock states come from the waypoints' depths over it).
    points : array_like
        ``(N, 3)`` waypoints (m).
    kinds : tuple of str
        ``(N,)`` the fix at each waypoint (``""``, ``"gps"``, ``"usbl"``).
    nav : NavParams
        The error model.
    usbl_xy : tuple of float, optional
        The USBL ship's local position (m).
    step : float, optional
        Sampling of the altitude schedule (m).
    held_water_m : array_like, optional
        ``(N,)`` the distance moved through the water while holding at each waypoint (m; module notes).
    water_m : array_like, optional
        ``(N - 1,)`` each leg's horizontal distance through the water (m; module notes); default: still water.
    launch_water_m : float, optional
        The launch's distance through the water (m; module notes): the budget counts the dive from the surface
        above the first waypoint; None: the mission starts at its first waypoint with ``σ = fix_error_m``.

    Returns
    -------
    NavBudget
        Errors at the waypoints and on the legs (the launch's largest error counts in ``max_error_m``).
    """
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    if len(kinds) != p.shape[0]:
        raise ValueError(f"{len(kinds)} fix kinds for {p.shape[0]} waypoints")
    cut = 0
    if launch_water_m is not None:
        p, kinds, held_water_m, water_m = _launched(p, kinds, held_water_m, water_m, launch_water_m)
        cut = 1
    ds, alt, leg, vertex = sample_route(world, p, step)
    lock = lock_fraction(alt, nav.dvl_range_m)
    inc = drift_increments(ds, lock, nav, water_lengths(ds, leg, water_m))
    held = hold_drift(alt[vertex], kinds, nav, held_water_m)
    inc[vertex[:-1]] += held[:-1]  # the hold before the leg that leaves the waypoint: its first interval
    inc = np.r_[inc, held[-1]]  # the last waypoint's hold: an interval of its own after the arrival
    fixes = [i for i, k in enumerate(kinds) if k and i > 0]
    before, after = sigma_profile(inc, vertex[fixes], [fix_sigma(nav, kinds[i], p[i], usbl_xy) for i in fixes],
                                  fix_sigma(nav, kinds[0] or "gps", p[0], usbl_xy))
    c = nav.confidence
    leg_error = c * before[vertex[1:]]  # σ grows along a leg: its largest is on arrival
    share = np.bincount(leg, weights=lock * ds, minlength=p.shape[0] - 1) / np.maximum(
        np.bincount(leg, weights=ds, minlength=p.shape[0] - 1), 1e-12)
    error = c * after[np.r_[vertex[:-1], vertex[-1] + 1]]  # the last waypoint's after its hold
    worst = float(max(leg_error.max(initial=0.0), error.max()))
    pieces = c * before[vertex[cut] + 1:vertex[-1] + 1]  # each interval's on arrival at its end (the launch's cut)
    return NavBudget(error[cut:], leg_error[cut:], share[cut:], tuple(kinds[cut:]), worst, pieces)


def error_profile(world: World, points: ArrayLike, kinds: tuple[str, ...], nav: NavParams,
                  usbl_xy: tuple[float, float] | None = None, step: float = DEFAULT_STEP_M,
                  water_m: ArrayLike | None = None, launch_water_m: float | None = None) -> ErrorProfile:
    """The predicted error at every sample of a mission whose fixes are known (:class:`ErrorProfile`); the
    same samples and σ as :func:`mission_budget`.

    Parameters
    ----------
    world : World
        The seabed.
    points : array_like
        ``(N, 3)`` waypoints (m).
    kinds : tuple of str
        ``(N,)`` the fix at each waypoint.
    nav : NavParams
        The error model.
    usbl_xy : tuple of float, optional
        The USBL ship's local position (m).
    step : float, optional
        Sampling (m).
    water_m : array_like, optional
        ``(N - 1,)`` each leg's horizontal distance through the water (m); default: still water.
    launch_water_m : float, optional
        The launch's distance through the water (m; :func:`mission_budget`); its dive counts in ``D``.

    Returns
    -------
    ErrorProfile
        The samples and the error before and after each (from the first waypoint, the launch's drift counted).
    """
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    cut = 0
    if launch_water_m is not None:
        p, kinds, _, water_m = _launched(p, kinds, None, water_m, launch_water_m)
        cut = 1  # the launch's one interval (a vertical leg): its first sample is the home
    ds, alt, leg, vertex = sample_route(world, p, step)
    inc = drift_increments(ds, lock_fraction(alt, nav.dvl_range_m), nav, water_lengths(ds, leg, water_m))
    fixes = [i for i, k in enumerate(kinds) if k and i > 0]
    before, after = sigma_profile(inc, vertex[fixes], [fix_sigma(nav, kinds[i], p[i], usbl_xy) for i in fixes],
                                  fix_sigma(nav, kinds[0] or "gps", p[0], usbl_xy))
    n = np.diff(vertex)
    k = np.arange(leg.size) - np.repeat(vertex[:-1], n)
    xyz = np.vstack([p[leg] + (k / n[leg])[:, None] * (p[leg + 1] - p[leg]), p[-1:]])[cut:]
    s = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(xyz, axis=0), axis=1))]
    fix = np.zeros(before.size, dtype=bool)
    fix[vertex[fixes]] = True
    return ErrorProfile(xyz, s, nav.confidence * before[cut:], nav.confidence * after[cut:], fix[cut:])
