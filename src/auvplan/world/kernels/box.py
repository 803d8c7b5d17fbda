"""The convex part of :meth:`World.segments_free`, compiled: both ends of each segment inside the depth band
and the bounds box.

The band and the box are convex, so a segment is inside when both its ends are.  The numpy formulation
(eight comparisons and a stacked minimum per call, some fifteen temporaries) was most of the cost of the
exact segment test on the elastic band's few dozen segments per pass (issue 59's CPU A/B); this kernel
makes the same comparisons in the same form (``-z >= min_depth``, ``-z <= max_depth``, each face's slack
``>= 0``; NaN fails every one), so the answer is the same boolean for every segment.
"""

from __future__ import annotations

from ..._types import BoolArray, FloatArray
from ...runtime.jit import kernel

__all__ = ["segments_in_box"]


@kernel
def segments_in_box(s: FloatArray, min_depth: float, max_depth: float, box: FloatArray,
                    out: BoolArray) -> None:  # pragma: no cover - compiled
    """Whether both ends of each segment are inside the depth band and the box.

    Parameters
    ----------
    s : numpy.ndarray
        Segments ``(N, 2, 3)`` (m), C-contiguous.
    min_depth, max_depth : float
        The depth band (m, positive down): ``min_depth <= -z <= max_depth``.
    box : numpy.ndarray
        ``(xmin, xmax, ymin, ymax, zmin, zmax)`` (m).
    out : numpy.ndarray
        ``(N,)`` of bool, filled.
    """
    for k in range(s.shape[0]):
        ok = True
        for e in range(2):
            x, y, z = s[k, e, 0], s[k, e, 1], s[k, e, 2]
            ok = ok and -z >= min_depth and -z <= max_depth
            ok = ok and x - box[0] >= 0.0 and box[1] - x >= 0.0 and y - box[2] >= 0.0 and box[3] - y >= 0.0
            ok = ok and z - box[4] >= 0.0 and box[5] - z >= 0.0
        out[k] = ok
