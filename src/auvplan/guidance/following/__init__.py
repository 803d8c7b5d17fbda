"""Route following: the polyline route and its active leg (:mod:`.route`), line-of-sight guidance (LOS, ILOS;
:mod:`.los`) and document 001's hybrid potential field (:mod:`.hybrid`)."""

__all__: list[str] = []
