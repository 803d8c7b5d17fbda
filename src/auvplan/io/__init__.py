"""Input and output: scenario files, bathymetry and current grids, result files and exports."""
