"""Path following (document 001 hybrid field, LOS, ILOS) and local avoidance of moving obstacles (document 004)."""
