"""The limits of a mission's world that are neither terrain nor obstacles: the operating area's box
(:class:`Bounds`, its signed distance and containment) and the vehicle's safety margins (:class:`Margins`).
The :class:`~auvplan.world.world.World` holds one of each.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._types import ArrayLike, BoolArray, FloatArray
from ..geometry import as_points

__all__ = ["Bounds", "Margins"]


@dataclass(frozen=True)
class Bounds:
    """Axis-aligned box of the operating area (m, local frame).

    Attributes
    ----------
    xmin, xmax, ymin, ymax : float
        Horizontal extent (x east, y north).
    zmin, zmax : float
        Vertical extent (z up; ``zmax = 0`` is the sea surface).

    Raises
    ------
    ValueError
        If a minimum is not below its maximum.
    """

    xmin: float
    xmax: float
    ymin: float
    ymax: float
    zmin: float
    zmax: float = 0.0

    def __post_init__(self) -> None:
        if not (self.xmin < self.xmax and self.ymin < self.ymax and self.zmin < self.zmax):
            raise ValueError(f"bounds must have min < max on every axis, got {self}")

    def slack(self, points: ArrayLike) -> FloatArray:
        """Signed distance to the nearest face.

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray
            ``(...)`` (m), positive inside.
        """
        p = as_points(points)
        x, y, z = p[..., 0], p[..., 1], p[..., 2]
        slack: FloatArray = np.minimum.reduce(
            [x - self.xmin, self.xmax - x, y - self.ymin, self.ymax - y, z - self.zmin, self.zmax - z]
        )
        return slack

    def contains(self, points: ArrayLike) -> BoolArray:
        """Where points lie inside the box (faces included).

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray of bool
            ``(...)``, True inside.
        """
        return self.slack(points) >= 0.0

    @property
    def diagonal(self) -> float:
        """Length of the box diagonal (m)."""
        return float(np.linalg.norm([self.xmax - self.xmin, self.ymax - self.ymin, self.zmax - self.zmin]))


@dataclass(frozen=True)
class Margins:
    """Safety margins of the vehicle (m).

    Attributes
    ----------
    min_altitude : float
        Minimum height above the seabed.
    min_depth : float
        Minimum depth below the sea surface (z ≤ -min_depth); ``-inf`` for a scene without a surface.
    max_depth : float
        Maximum depth (z ≥ -max_depth).
    obstacle : float
        Minimum distance to any obstacle surface.

    Raises
    ------
    ValueError
        If a margin is negative or ``max_depth`` does not exceed ``min_depth``.
    """

    min_altitude: float = 0.0
    min_depth: float = 0.0
    max_depth: float = float("inf")
    obstacle: float = 0.0

    def __post_init__(self) -> None:
        if self.min_altitude < 0 or (self.min_depth < 0 and self.min_depth != -float("inf")) or self.obstacle < 0:
            raise ValueError(f"margins must be non-negative, got {self}")
        if not self.max_depth > self.min_depth:
            raise ValueError(f"max_depth must exceed min_depth, got {self}")
