"""Geometric helpers shared by every layer (frame: x east, y north, z up, metres).

Headings are compass angles, clockwise from north, in radians; pitch is
positive nose-up.
"""

from __future__ import annotations

import numpy as np

from ._types import ArrayLike, FloatArray

__all__ = [
    "wrap_angle",
    "heading_of",
    "unit_from_heading_pitch",
    "rotation_matrix",
    "point_segment_distance",
    "as_points",
]


def as_points(points: ArrayLike, name: str = "points") -> FloatArray:
    """Return ``points`` as a float array of shape ``(..., 3)``.

    Parameters
    ----------
    points : array_like
        Points ``(..., 3)`` (x east, y north, z up; m).
    name : str, default "points"
        Name used in the error message.

    Returns
    -------
    numpy.ndarray
        Float64 array ``(..., 3)`` (a view when ``points`` already is one).

    Raises
    ------
    ValueError
        If the last axis does not have length 3.
    """
    arr: FloatArray = np.asarray(points, dtype=np.float64)
    if arr.shape[-1:] != (3,):
        raise ValueError(f"{name} must have shape (..., 3), got {arr.shape}")
    return arr


def wrap_angle(a: ArrayLike) -> FloatArray:
    """Wrap angles to ``[-pi, pi)``.

    Parameters
    ----------
    a : array_like
        Angles (rad), any shape.

    Returns
    -------
    numpy.ndarray
        The same angles wrapped to ``[-pi, pi)`` (rad), same shape.
    """
    wrapped: FloatArray = (np.asarray(a) + np.pi) % (2.0 * np.pi) - np.pi
    return wrapped


def heading_of(vectors: ArrayLike) -> FloatArray:
    """Compass heading (clockwise from north) of the horizontal part of vectors.

    Parameters
    ----------
    vectors : array_like
        Vectors ``(..., >=2)``; only the east and north components are used.

    Returns
    -------
    numpy.ndarray
        Headings ``(...)`` (rad, clockwise from north, in ``[-pi, pi]``).
    """
    v = np.asarray(vectors, dtype=np.float64)
    heading: FloatArray = np.arctan2(v[..., 0], v[..., 1])
    return heading


def unit_from_heading_pitch(heading: ArrayLike, pitch: ArrayLike) -> FloatArray:
    """Unit vectors for compass heading and nose-up pitch.

    Parameters
    ----------
    heading : array_like
        Compass heading (rad, clockwise from north).
    pitch : array_like
        Pitch (rad, positive nose-up); broadcasts with ``heading``.

    Returns
    -------
    numpy.ndarray
        Unit vectors ``(..., 3)`` (east, north, up).
    """
    heading = np.asarray(heading, dtype=float)
    pitch = np.asarray(pitch, dtype=float)
    cp = np.cos(pitch)
    return np.stack([cp * np.sin(heading), cp * np.cos(heading), np.sin(pitch)], axis=-1)


def rotation_matrix(yaw: float = 0.0, pitch: float = 0.0, roll: float = 0.0) -> FloatArray:
    """Body-to-world rotation for a body whose x axis points along (yaw, pitch).

    Intrinsic z-y-x order.

    Parameters
    ----------
    yaw : float, default 0.0
        Rotation about the world z axis, counter-clockwise from the world x (east) axis (rad).
    pitch : float, default 0.0
        Rotation lifting the body x axis up out of the horizontal plane (rad).
    roll : float, default 0.0
        Rotation of the body about its own x axis (rad).

    Returns
    -------
    numpy.ndarray
        Rotation matrix ``(3, 3)``; ``R @ v_body`` is ``v`` in the world frame.
    """
    cy, sy = np.cos(yaw), np.sin(yaw)
    cp, sp = np.cos(pitch), np.sin(pitch)
    cr, sr = np.cos(roll), np.sin(roll)
    rz = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
    # positive pitch lifts the body x axis towards +z
    ry = np.array([[cp, 0.0, -sp], [0.0, 1.0, 0.0], [sp, 0.0, cp]])
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    r: FloatArray = rz @ ry @ rx
    return r


def point_segment_distance(points: ArrayLike, a: ArrayLike, b: ArrayLike) -> FloatArray:
    """Distance from points to segments ``a -> b``.

    Parameters
    ----------
    points : array_like
        Points ``(..., 3)`` (m).
    a, b : array_like
        Segment ends ``(..., 3)`` (m); broadcast with ``points``.

    Returns
    -------
    numpy.ndarray
        Euclidean distances ``(...)`` (m) to the closest point of each segment.
    """
    p = np.asarray(points, dtype=np.float64)
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    d = b - a
    dd = np.einsum("...i,...i->...", d, d)
    t = np.einsum("...i,...i->...", p - a, d) / np.where(dd > 0.0, dd, 1.0)
    t = np.clip(t, 0.0, 1.0)
    closest = a + t[..., None] * d
    dist: FloatArray = np.linalg.norm(p - closest, axis=-1)
    return dist
