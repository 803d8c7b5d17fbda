"""Paths: clamped cubic B-splines and polylines (:mod:`.curves`), depth profiles within a pitch limit
(:mod:`.pitch`), and what a vehicle can fly along a polyline (:mod:`.flyable`).

The names of :mod:`.curves` are re-exported here (``from auvplan.path import BSplinePath``).
"""

from __future__ import annotations

from .curves import (
    BSplinePath,
    arc_length,
    basis_matrix,
    clamped_knots,
    densify,
    polyline_length,
    resample_polyline,
    sample_population,
    uniform_cubic_basis,
)

__all__ = ["uniform_cubic_basis", "clamped_knots", "basis_matrix", "BSplinePath", "sample_population",
           "polyline_length", "arc_length", "resample_polyline", "densify"]
