"""What a scenario's inputs become in its World beyond the tables: geographic positions (:mod:`.geoinput`),
currents needed past a file's time span (:mod:`.currentspan`), the members of a forecast ensemble
(:mod:`.members`) and the seabed at a confidence (:mod:`.uncertainty`)."""

__all__: list[str] = []
