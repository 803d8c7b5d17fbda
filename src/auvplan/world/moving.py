"""Moving obstacles: a shape (:mod:`auvplan.world.obstacles`) whose centre follows a motion model —
linear, circle, waypoint loop or a seeded random walk (document 004's "irregular" motion, pre-computed
so that it is deterministic and cheap to query) — and exists from ``appears`` to ``disappears``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .._types import ArrayLike, FloatArray
from .obstacles import Shape

__all__ = [
    "LinearMotion",
    "CircleMotion",
    "WaypointMotion",
    "RandomWalkMotion",
    "Motion",
    "MovingObstacle",
]


@dataclass(frozen=True)
class LinearMotion:
    """Constant velocity from a start point.

    Parameters
    ----------
    start : tuple of float
        Position at t = 0 (m).
    velocity : tuple of float
        Velocity (m/s).
    """

    start: tuple[float, float, float]
    velocity: tuple[float, float, float]

    def position(self, t: ArrayLike) -> FloatArray:
        """Centre at times.

        Parameters
        ----------
        t : array_like
            Time (s), scalar or ``(T,)``.

        Returns
        -------
        numpy.ndarray
            ``(3,)`` or ``(T, 3)`` (m).
        """
        t = np.asarray(t, dtype=float)
        centre: FloatArray = np.asarray(self.start) + t[..., None] * np.asarray(self.velocity)
        return centre

    @property
    def speed(self) -> float:
        """Largest speed of the centre.

        Returns
        -------
        float
            Speed (m/s).
        """
        return float(np.linalg.norm(self.velocity))


@dataclass(frozen=True)
class CircleMotion:
    """Horizontal circle of ``radius`` about ``center`` with ``period`` (s); counter-clockwise when ``period > 0``.

    Parameters
    ----------
    center : tuple of float
        Centre of the circle (m).
    radius : float
        Radius (m), positive.
    period : float
        Time of one turn (s), non-zero; negative turns clockwise.
    phase : float, default 0.0
        Angle at t = 0, counter-clockwise from east (rad).

    Raises
    ------
    ValueError
        If the radius is not positive or the period is zero.
    """

    center: tuple[float, float, float]
    radius: float
    period: float
    phase: float = 0.0

    def __post_init__(self) -> None:
        if self.period == 0 or self.radius <= 0:
            raise ValueError("circle motion needs a positive radius and a non-zero period")

    def position(self, t: ArrayLike) -> FloatArray:
        """Centre at times.

        Parameters
        ----------
        t : array_like
            Time (s), scalar or ``(T,)``.

        Returns
        -------
        numpy.ndarray
            ``(3,)`` or ``(T, 3)`` (m).
        """
        t = np.asarray(t, dtype=float)
        ang = self.phase + 2.0 * np.pi * t / self.period
        off = np.stack([np.cos(ang), np.sin(ang), np.zeros_like(ang)], axis=-1) * self.radius
        return np.asarray(self.center) + off

    @property
    def speed(self) -> float:
        """Largest speed of the centre.

        Returns
        -------
        float
            Speed (m/s).
        """
        return float(2.0 * np.pi * self.radius / abs(self.period))


@dataclass(frozen=True, eq=False)
class WaypointMotion:
    """Constant speed along a polyline.

    Parameters
    ----------
    points : array_like
        Vertices ``(K, 3)`` (m), ``K >= 2``.
    speed : float
        Speed of the centre (m/s), positive.
    loop : bool, default True
        Close the polyline into a loop (else stop at the last vertex).

    Raises
    ------
    ValueError
        With fewer than two points or a speed that is not positive.
    """

    points: FloatArray
    speed: float
    loop: bool = True
    _s: FloatArray = field(init=False, repr=False)
    _pts: FloatArray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        pts = np.asarray(self.points, dtype=float).reshape(-1, 3)
        if pts.shape[0] < 2 or self.speed <= 0:
            raise ValueError("waypoint motion needs at least two points and a positive speed")
        if self.loop:
            pts = np.vstack([pts, pts[:1]])
        s = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))]
        object.__setattr__(self, "points", np.asarray(self.points, dtype=float).reshape(-1, 3))
        object.__setattr__(self, "_pts", pts)
        object.__setattr__(self, "_s", s)

    def position(self, t: ArrayLike) -> FloatArray:
        """Centre at times.

        Parameters
        ----------
        t : array_like
            Time (s), scalar or ``(T,)``.

        Returns
        -------
        numpy.ndarray
            ``(3,)`` or ``(T, 3)`` (m).
        """
        t = np.asarray(t, dtype=float)
        d = self.speed * t
        d = np.mod(d, self._s[-1]) if self.loop else np.clip(d, 0.0, self._s[-1])
        return np.stack([np.interp(d, self._s, self._pts[:, k]) for k in range(3)], axis=-1)


@dataclass(frozen=True, eq=False)
class RandomWalkMotion:
    """Seeded random walk: constant speed, heading diffusing with ``turn_sigma`` (rad/√s).

    The track is pre-computed at ``dt`` over ``duration`` seconds (then it
    stays put), reflected off the horizontal box ``bounds = (xmin, xmax, ymin, ymax)``
    when given.  The same ``seed`` gives the same track.

    Parameters
    ----------
    start : tuple of float
        Position at t = 0 (m); the depth stays.
    speed : float
        Speed (m/s), non-negative.
    turn_sigma : float, default 0.05
        Heading diffusion (rad/√s).
    heading : float, default 0.0
        Initial compass heading (rad).
    duration : float, default 7200.0
        Length of the pre-computed track (s).
    dt : float, default 1.0
        Track step (s).
    seed : int, default 0
        Seed of the track's generator.
    bounds : tuple of float, optional
        ``(xmin, xmax, ymin, ymax)`` (m) to reflect the walk off.

    Raises
    ------
    ValueError
        If speed < 0, dt <= 0 or duration <= 0.
    """

    start: tuple[float, float, float]
    speed: float
    turn_sigma: float = 0.05
    heading: float = 0.0
    duration: float = 7200.0
    dt: float = 1.0
    seed: int = 0
    bounds: tuple[float, float, float, float] | None = None
    _track: FloatArray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if self.speed < 0 or self.dt <= 0 or self.duration <= 0:
            raise ValueError("random walk needs speed >= 0, dt > 0 and duration > 0")
        rng = np.random.default_rng(self.seed)
        n = int(np.ceil(self.duration / self.dt))
        psi = self.heading + np.cumsum(rng.normal(0.0, self.turn_sigma * np.sqrt(self.dt), n))
        step = self.speed * self.dt * np.stack([np.sin(psi), np.cos(psi)], axis=-1)
        xy = np.asarray(self.start[:2], dtype=float) + np.vstack([np.zeros(2), np.cumsum(step, axis=0)])
        if self.bounds is not None:
            lo = np.array([self.bounds[0], self.bounds[2]])
            hi = np.array([self.bounds[1], self.bounds[3]])
            width = hi - lo
            # reflect: fold the unconstrained walk into the box
            r = np.mod(xy - lo, 2.0 * width)
            xy = lo + np.where(r > width, 2.0 * width - r, r)
        track = np.column_stack([xy, np.full(n + 1, float(self.start[2]))])
        object.__setattr__(self, "_track", track)

    def position(self, t: ArrayLike) -> FloatArray:
        """Centre at times.

        Parameters
        ----------
        t : array_like
            Time (s), scalar or ``(T,)``.

        Returns
        -------
        numpy.ndarray
            ``(3,)`` or ``(T, 3)`` (m).
        """
        t = np.asarray(t, dtype=float)
        k = np.clip(t / self.dt, 0.0, self._track.shape[0] - 1.0)
        i = np.minimum(np.floor(k).astype(np.intp), self._track.shape[0] - 2)
        f = (k - i)[..., None]
        centre: FloatArray = self._track[i] * (1.0 - f) + self._track[i + 1] * f
        return centre


Motion = LinearMotion | CircleMotion | WaypointMotion | RandomWalkMotion


@dataclass(frozen=True)
class MovingObstacle:
    """A shape whose centre follows ``motion``; the shape's own centre is ignored.

    Parameters
    ----------
    shape : Sphere or Ellipsoid
        The body; its own centre is ignored.
    motion : LinearMotion or CircleMotion or WaypointMotion or RandomWalkMotion
        Path of the centre.
    name : str
        Free text.
    appears : float, default 0.0
        Time the obstacle starts to exist (s).
    disappears : float, default inf
        Time it stops existing (s; finite for an obstacle removed mid-mission).
    """

    shape: Shape
    motion: Motion
    name: str = ""
    appears: float = 0.0
    disappears: float = float("inf")

    def center(self, t: float) -> FloatArray:
        """Centre at a time.

        Parameters
        ----------
        t : float
            Time (s).

        Returns
        -------
        numpy.ndarray
            ``(3,)`` (m).
        """
        return self.motion.position(t)

    def velocity(self, t: float, h: float = 0.05) -> FloatArray:
        """Centre velocity by a central difference (one-sided at t = 0).

        Parameters
        ----------
        t : float
            Time (s).
        h : float, default 0.05
            Half step of the difference (s).

        Returns
        -------
        numpy.ndarray
            ``(3,)`` (m/s).
        """
        return (self.motion.position(t + h) - self.motion.position(max(t - h, 0.0))) / (t + h - max(t - h, 0.0))

    def active(self, t: float) -> bool:
        """Whether the obstacle exists at a time.

        Parameters
        ----------
        t : float
            Time (s).

        Returns
        -------
        bool
            ``appears <= t < disappears``.
        """
        return self.appears <= t < self.disappears

    def at(self, t: float) -> Shape:
        """The obstacle's shape placed at its position at a time.

        Parameters
        ----------
        t : float
            Time (s).

        Returns
        -------
        Sphere or Ellipsoid
            The shape about :meth:`center` ``(t)``.
        """
        return self.shape.moved_to(self.center(t))
