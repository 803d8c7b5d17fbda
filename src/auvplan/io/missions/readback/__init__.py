"""Mission files read back (``auvplan mission check``): the parsers of every format (:mod:`.parsers`, a ``.plan``'s
items :mod:`.qgc_items`), the file read and re-flown (:mod:`.readers`), each leg's speed (:mod:`.speeds`), the
terrain-following legs (:mod:`.terrain_frame`), the position fixes (:mod:`.fixes`) and what makes the file deployable
(:mod:`.deploy_read`)."""

__all__: list[str] = []
