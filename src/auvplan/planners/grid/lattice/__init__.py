"""The lean 3D lattice of the reference planner: node fields, free edges and the compiled search.

Memory grows with the nodes, not with the 26 edges of each node, and no array the size of the
lattice is held twice:

* **Node fields** (:func:`node_fields`) are evaluated one slab of x at a time: the World's
  constraints on the slab's points, the seabed and the land (horizontal fields) once per column.
  What the edge test needs is kept in single precision rounded towards the safe side (altitude and
  obstacle clearance rounded down), the current in single precision.
* **Free edges** (:func:`edge_bits`) are one bit per lattice direction and node.  One compiled
  pass per direction clears most edges from the node values alone (the seabed's Lipschitz bound,
  the obstacles' 1-Lipschitz distance); the few others go through the World's exact segment test.
* **The search** (:func:`search`) is Dijkstra from the goal over the reversed lattice with an
  indexed binary heap (``int32`` indices), edges and their costs generated on the fly.  Given a
  start it becomes A*: the heuristic ``c_min |x - start|`` with ``c_min`` the cheapest cost per
  metre any edge can have (length weight, plus the energy of travelling at the vehicle's speed
  plus the strongest current), which is consistent, so the first settled value of every node is
  its cost-to-go and the search stops as soon as no unsettled node can lead to a cheaper start.

The package, one idea a module: :mod:`.nodes` (the lattice directions and the node fields),
:mod:`.edges` (the edge test, its states and bits) and :mod:`.dijkstra` (edge weights and the search).
"""

from __future__ import annotations

from .dijkstra import search
from .edges import edge_bits, edge_states, lattice_slopes
from .edges import free_edges as free_edges
from .nodes import HALF, OFFSETS, down32, node_fields

__all__ = ["HALF", "OFFSETS", "node_fields", "edge_bits", "edge_states", "lattice_slopes", "search", "down32"]
