"""The jobs of the planning page (``auvplan serve``), data in, data out: the mission check and the energy budget of a
mission held in memory, re-flying only the legs an edit changed (:mod:`.check`, :mod:`.budget`, their per-leg cache
:mod:`.lru`), the surveys, plans and flights it asks for (:mod:`.plans`), file access confined to the folders it was
started with (:mod:`.paths`) and a scenario written back as TOML (:mod:`.tomlout`)."""

__all__: list[str] = []
