"""Vector feature files: the one reader (:mod:`.reader`), coastlines (:mod:`.coast`), charted zones
(:mod:`.zones`, their tables :mod:`.zone_tables` and footprints :mod:`.footprints`) and survey areas and centre
lines (:mod:`.areas`)."""

from .reader import VectorLayer, read_vector

__all__ = ["VectorLayer", "read_vector"]
