"""Results folders: run records and the files beside them."""

__all__: list[str] = []
