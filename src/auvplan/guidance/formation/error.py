"""Formation error figures of one vehicle: whole run and settled (after the launch transient).

A vehicle launched off its slot (``[formation] start_sigma_m``, the launch scatter) starts with an
error of tens of metres that the guidance closes in a minute or two; the largest error of the whole
run is then the launch offset, not how well the formation is kept.  :func:`error_figures` reports
both: the whole run, and the run *settled*, from the first recorded step at which the vehicle is
within ``settle_m`` of its slot (every later excursion — a turn away from a moving obstacle, a shape
change — counts).  A vehicle that never comes within ``settle_m`` has no settled part (NaN figures,
``settle_time_s`` inf).
"""

from __future__ import annotations

import math

import numpy as np

from ..._types import ArrayLike

__all__ = ["SETTLE_M", "error_figures"]

SETTLE_M = 10.0
"""Default settling radius (m): a vehicle is settled from its first step within this of its slot."""


def _stats(e: np.ndarray, prefix: str) -> dict[str, float]:
    if e.size == 0:
        return {f"{prefix}_rms_m": math.nan, f"{prefix}_p95_m": math.nan, f"{prefix}_max_m": math.nan}
    return {f"{prefix}_rms_m": float(np.sqrt(np.mean(e**2))), f"{prefix}_p95_m": float(np.percentile(e, 95.0)),
            f"{prefix}_max_m": float(e.max())}


def error_figures(t: ArrayLike, err: ArrayLike, settle_m: float = SETTLE_M) -> dict[str, float]:
    """Formation error figures of one vehicle's recorded run.

    Parameters
    ----------
    t : array_like (N,)
        Times of the recorded steps (s), increasing.
    err : array_like (N,)
        Distance from the vehicle to its slot at those steps (m).
    settle_m : float
        Settling radius (m, > 0).

    Returns
    -------
    dict
        ``formation_error_rms_m``, ``formation_error_p95_m``, ``formation_error_max_m`` over the
        whole run; ``settle_time_s`` (time of the first step within ``settle_m``, measured from the
        first step; inf if never); ``settled_error_rms_m``, ``settled_error_p95_m``,
        ``settled_error_max_m`` from that step to the end (NaN if never settled).  Empty input: the
        whole-run figures are 0.
    """
    if not settle_m > 0:
        raise ValueError(f"settle_m = {settle_m}: must be positive")
    tt = np.asarray(t, dtype=float)
    e = np.asarray(err, dtype=float)
    if tt.shape != e.shape:
        raise ValueError(f"t has shape {tt.shape}, err {e.shape}: must match")
    if e.size == 0:
        out = {"formation_error_rms_m": 0.0, "formation_error_p95_m": 0.0, "formation_error_max_m": 0.0}
    else:
        out = _stats(e, "formation_error")
    inside = np.flatnonzero(e <= settle_m)
    k = int(inside[0]) if inside.size else e.size
    out["settle_time_s"] = float(tt[k] - tt[0]) if inside.size else math.inf
    out.update(_stats(e[k:], "settled_error"))
    return out
