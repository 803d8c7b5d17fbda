"""Bathymetric uncertainty: a per-cell vertical uncertainty and the worst-case seabed at a confidence (issue 39).

A seabed grid ``z`` (m, up) comes with a one-sigma vertical uncertainty ``σ`` per node: from the data
file's own uncertainty layer (GEBCO-style), a constant, or the **slope rule**: a feature between two
nodes ``h`` apart on a local slope ``|∇z|`` can stand up to half a cell's rise above the interpolated
seabed, so ``σ = √(σ₀² + (h |∇z| / 2)²)`` with ``h`` the larger grid spacing and ``σ₀`` a floor
(the survey's own accuracy).  Errors are taken as Gaussian and independent per node; the worst-case
seabed at confidence ``p`` is ``z + Φ⁻¹(p) σ`` (one-sided: the seabed lies below it with probability p
at every node; Φ⁻¹(0.95) = 1.6449), and clearance above it is reported as "x m at 95 %".
"""

from __future__ import annotations

import numpy as np

from .._types import ArrayLike, FloatArray
from .terrain import Terrain

__all__ = ["z_score", "slope_sigma", "worst_case"]


def z_score(confidence: float) -> float:
    """One-sided standard normal quantile Φ⁻¹(confidence).

    Parameters
    ----------
    confidence : float
        In (0, 1).

    Returns
    -------
    float
        The quantile (1.6449 at 0.95).
    """
    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence = {confidence}: must lie in (0, 1)")
    from scipy.stats import norm  # imported when used: scipy.stats costs ~0.5 s of a command's start (#56)

    return float(norm.ppf(confidence))


def slope_sigma(terrain: Terrain, floor_m: float = 0.0) -> FloatArray:
    """The slope rule's one-sigma vertical uncertainty at every node (module notes).

    Parameters
    ----------
    terrain : Terrain
        The seabed grid.
    floor_m : float, default 0.0
        σ₀ (m), >= 0.

    Returns
    -------
    numpy.ndarray
        ``σ`` (m), the shape of ``terrain.z``.
    """
    if floor_m < 0:
        raise ValueError(f"floor_m = {floor_m}: must be >= 0")
    x, y, z = (np.asarray(a, dtype=float) for a in (terrain.x, terrain.y, terrain.z))
    gy, gx = np.gradient(z, y, x)
    h = max(float(np.max(np.diff(x))), float(np.max(np.diff(y))))
    out: FloatArray = np.sqrt(floor_m**2 + (0.5 * h * np.hypot(gx, gy)) ** 2)
    return out


def worst_case(terrain: Terrain, sigma: ArrayLike, confidence: float) -> Terrain:
    """The seabed raised by Φ⁻¹(confidence) σ: what plans and checks hold against at that confidence.

    Parameters
    ----------
    terrain : Terrain
        The nominal seabed.
    sigma : array_like
        One-sigma vertical uncertainty (m), a scalar or the shape of ``terrain.z``; >= 0.
    confidence : float
        In (0.5, 1).

    Returns
    -------
    Terrain
        The worst-case seabed on the same grid, named ``"<name> (worst case at 95 %)"``.
    """
    s = np.broadcast_to(np.asarray(sigma, dtype=float), np.shape(terrain.z))
    if not np.all(np.isfinite(s)) or np.any(s < 0):
        raise ValueError("the vertical uncertainty must be finite and >= 0 everywhere")
    if not 0.5 < confidence < 1.0:
        raise ValueError(f"confidence = {confidence}: must lie in (0.5, 1)")
    z = np.asarray(terrain.z, dtype=float) + z_score(confidence) * s
    pct = f"{100.0 * confidence:g}"
    return Terrain(terrain.x, terrain.y, z, name=f"{terrain.name} (worst case at {pct} %)", fit=terrain.fit)

