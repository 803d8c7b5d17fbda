"""Input data: bathymetry, elevation grids, currents, tides, coastlines, and the local frame."""

__all__: list[str] = []
