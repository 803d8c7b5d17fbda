"""The streamline planner of document 000: potential-flow field, bodies, streamlines."""

__all__: list[str] = []
