"""Geometric helpers shared by every layer (frame: x east, y north, z up, metres).

Headings are compass angles, clockwise from north, in radians; pitch is
positive nose-up.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "wrap_angle",
    "heading_of",
    "unit_from_heading_pitch",
    "rotation_matrix",
    "point_segment_distance",
    "as_points",
]


def as_points(points, name: str = "points") -> np.ndarray:
    """Return ``points`` as a float array of shape ``(..., 3)``; raise ``ValueError`` otherwise."""
    arr = np.asarray(points, dtype=float)
    if arr.shape[-1:] != (3,):
        raise ValueError(f"{name} must have shape (..., 3), got {arr.shape}")
    return arr


def wrap_angle(a):
    """Wrap angles to ``[-pi, pi)``."""
    return (np.asarray(a) + np.pi) % (2.0 * np.pi) - np.pi


def heading_of(vectors) -> np.ndarray:
    """Compass heading (clockwise from north) of the horizontal part of ``vectors`` ``(..., >=2)``."""
    v = np.asarray(vectors, dtype=float)
    return np.arctan2(v[..., 0], v[..., 1])


def unit_from_heading_pitch(heading, pitch) -> np.ndarray:
    """Unit vectors ``(..., 3)`` for compass heading and nose-up pitch (radians)."""
    heading = np.asarray(heading, dtype=float)
    pitch = np.asarray(pitch, dtype=float)
    cp = np.cos(pitch)
    return np.stack([cp * np.sin(heading), cp * np.cos(heading), np.sin(pitch)], axis=-1)


def rotation_matrix(yaw: float = 0.0, pitch: float = 0.0, roll: float = 0.0) -> np.ndarray:
    """Body-to-world rotation for a body whose x axis points along (yaw, pitch).

    ``yaw`` is measured counter-clockwise from the world x (east) axis about z,
    ``pitch`` rotates the body x axis up out of the horizontal plane and ``roll``
    turns the body about its own x axis (intrinsic z-y-x order, all radians).
    """
    cy, sy = np.cos(yaw), np.sin(yaw)
    cp, sp = np.cos(pitch), np.sin(pitch)
    cr, sr = np.cos(roll), np.sin(roll)
    rz = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
    # positive pitch lifts the body x axis towards +z
    ry = np.array([[cp, 0.0, -sp], [0.0, 1.0, 0.0], [sp, 0.0, cp]])
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    return rz @ ry @ rx


def point_segment_distance(points, a, b) -> np.ndarray:
    """Distance from ``points (..., 3)`` to segments ``a -> b`` (broadcasting ``(..., 3)``)."""
    p = np.asarray(points, dtype=float)
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    d = b - a
    dd = np.einsum("...i,...i->...", d, d)
    t = np.einsum("...i,...i->...", p - a, d) / np.where(dd > 0.0, dd, 1.0)
    t = np.clip(t, 0.0, 1.0)
    closest = a + t[..., None] * d
    return np.linalg.norm(p - closest, axis=-1)
