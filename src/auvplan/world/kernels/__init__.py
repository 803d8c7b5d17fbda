"""The compiled kernels of the seabed's heightfield and of the ellipsoids' distances."""

__all__: list[str] = []
