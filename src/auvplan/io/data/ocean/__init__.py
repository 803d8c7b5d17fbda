"""Ocean data: current files (regular grids, ROMS, vector rotation) and tide tables."""

__all__: list[str] = []
