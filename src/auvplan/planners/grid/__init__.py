"""The lattice reference planner: Dijkstra / A* on a 26-connected lattice, band refinement."""

__all__: list[str] = []
