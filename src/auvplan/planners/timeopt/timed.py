"""The current table and the timed paths of the time-dependent search (:mod:`.search`): the field sampled at the
lattice nodes every ``dt`` seconds, the times a vehicle holding a polyline at a through-water speed reaches its
vertices (:func:`timed_traverse`), and whether the water a current pushes it back into is free (:func:`drift_free`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..._types import ArrayLike, BoolArray, FloatArray
from ...world import World
from .kernels import Float32Array, polyline_times

__all__ = ["CurrentTable", "TimedPath", "timed_traverse", "drift_free"]


@dataclass(frozen=True, eq=False)
class CurrentTable:
    """The field at the lattice nodes every ``dt`` seconds from ``t0``: ``cur (nt, nx, ny, nz, 3)``
    (single precision: a tidal table of a 50 km strait over a day is tens of megabytes).

    Parameters
    ----------
    cur : numpy.ndarray
        Current ``(nt, nx, ny, nz, 3)`` (m/s, float32).
    origin, step : numpy.ndarray
        First node and node spacing of the lattice ``(3,)`` (m).
    t0 : float
        Time of the first slice (s).
    dt : float
        Time between slices (s).
    """

    cur: Float32Array
    origin: FloatArray
    step: FloatArray
    t0: float
    dt: float

    @property
    def t1(self) -> float:
        """Last time of the table.

        Returns
        -------
        float
            ``t0 + dt (nt - 1)`` (s).
        """
        t1: float = self.t0 + self.dt * (self.cur.shape[0] - 1)
        return t1

    def args(self) -> tuple[Float32Array, FloatArray, FloatArray, float, float]:
        """The leading arguments of the kernels.

        Returns
        -------
        tuple
            ``(cur, origin, step, t0, dt)``.
        """
        return self.cur, self.origin, self.step, self.t0, self.dt


@dataclass(frozen=True, eq=False)
class TimedPath:
    """A path with the time the vehicle reaches each vertex.

    Parameters
    ----------
    points : numpy.ndarray
        Vertices ``(N, 3)`` (m).
    times : numpy.ndarray
        Arrival at each vertex ``(N,)`` (s after the mission's start time).
    speed : float
        Through-water speed (m/s).
    back : numpy.ndarray, optional
        How far behind its start the current pushed the vehicle on each leg ``(N - 1,)`` (m;
        None: not known, as for a lattice path).
    tail : numpy.ndarray of bool, optional
        ``(N - 1,)``: the legs flown tail-first (:mod:`.tail`; None: none).
    timed : bool, default False
        The times are already those of a flight through the World's own current (the front method,
        :mod:`.front_plan`): :func:`.planner.flown` keeps them.
    """

    points: FloatArray
    times: FloatArray
    speed: float
    back: FloatArray | None = None
    tail: BoolArray | None = None
    timed: bool = False

    @property
    def duration(self) -> float:
        """Travel time.

        Returns
        -------
        float
            Last minus first time (s); ``inf`` when the current blocks the path somewhere.
        """
        return float(self.times[-1] - self.times[0]) if self.times.size else math.inf


def timed_traverse(table: CurrentTable, points: ArrayLike, depart: float, speed: float, ds: float) -> TimedPath:
    """Times along a polyline flown at a through-water speed (holding the track).

    Parameters
    ----------
    table : CurrentTable
        The time-varying current.
    points : array_like
        Vertices ``(N, 3)`` (m).
    depart : float
        Departure time from the first vertex (s).
    speed : float
        Through-water speed (m/s).
    ds : float
        Largest integration sub-step (m).

    Returns
    -------
    TimedPath
        The polyline with its arrival times (``inf`` after a rejected leg) and each leg's drift.
    """
    p = np.ascontiguousarray(np.asarray(points, dtype=float))
    out, back = np.empty(p.shape[0]), np.zeros(max(p.shape[0] - 1, 0))
    polyline_times(*table.args(), p, float(depart), float(speed), float(ds), out, back)
    return TimedPath(p, out, float(speed), back)


def drift_free(world: World, tp: TimedPath) -> bool:
    """Whether the water behind each leg's start that the current pushes the vehicle back into is free.

    Parameters
    ----------
    world : World
        The world of the exact segment tests.
    tp : TimedPath
        A path with its drifts (``back``; None passes).

    Returns
    -------
    bool
        True when every leg's stretch ``[start - back ŝ, start]`` passes the exact segment test.
    """
    if tp.back is None or not (tp.back > 0.0).any():
        return True
    i = np.flatnonzero(tp.back > 0.0)
    d = tp.points[i + 1] - tp.points[i]
    e = d / np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-12)
    seg = np.stack([tp.points[i] - tp.back[i, None] * e, tp.points[i]], axis=1)
    return bool(world.segments_free(seg, moving=False).all())
