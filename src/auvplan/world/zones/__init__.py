"""Charted hazards and no-go zones in 3D: a footprint in the local frame times a depth band.

A :class:`Zone` is a closed prism: a polygonal footprint (a charted area, a cable or pipeline
corridor buffered about its line, a circle round a wreck) in the local metric frame (x east,
y north, m) times a vertical band, either

* between two depths (``top`` and ``bottom``, positive down; ``bottom = inf`` reaches the
  seabed), i.e. ``-bottom <= z <= -top``; or
* from the seabed up to ``above_seabed`` metres above it (a hazard lying on the seabed), i.e.
  ``z <= zb(x, y) + above_seabed``.

:class:`Zones` holds many of them behind a shapely ``STRtree`` over the footprints, so a
thousand zones cost a bulk index query, not a thousand tests.  Its queries, vectorised:

* :meth:`Zones.entries` — the **exact** segment-vs-prism test.  A flat band cuts the segment
  parameter to one interval (z is linear along the segment); the segment's horizontal trace over
  that interval is tested against the footprint with GEOS ``intersects``.  A seabed band clips
  the trace to the footprint (GEOS ``intersection``; every piece of a straight trace is a
  straight sub-segment) and tests each piece's least altitude with the terrain's exact walk
  (:meth:`Terrain.segment_min_altitude`).  No sampling anywhere; the prism is closed (touching
  a face is an entry).
* :meth:`Zones.signed_distance` — distance from points to the nearest prism, negative inside.
  For a flat band it is the Euclidean distance ``hypot(d_h, d_v)`` (exact: the prism is a
  product set); for a seabed band the vertical term is ``(z - zb - h) / sqrt(1 + G^2)`` with
  ``G`` the steepest seabed slope, a lower bound of the true distance, so the value is never
  above the true clearance (what the planners' Lipschitz shortcuts need).

The package: :mod:`.spec` (:class:`Zone`, :class:`ZoneApproach`), :mod:`.index` (the prisms, padded or
:attr:`Zones.exact`, their R-tree, the broad phase's grid and fine field), :mod:`.segments` (the segment
queries), :mod:`.points` (the point queries: :class:`Zones`), the compiled parts (:mod:`.kernels`: the any-hit
passes, over :mod:`.broad`: the cells' walk, :mod:`.bound`: the fine field per depth slab, and :mod:`.exact`:
the exact tests) and :mod:`.parts`
(geometry helpers).
"""

from .points import Zones
from .spec import Zone, ZoneApproach

__all__ = ["Zone", "Zones", "ZoneApproach"]
