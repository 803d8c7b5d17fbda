"""Files in and out, guarded: bounded JSON reading (:mod:`.jsonfile`), a scenario's resource budget checked before
allocation (:mod:`.limits`), the locked ``--out`` folders (:mod:`.outdir`), atomic writes that never overwrite a
user's file (:mod:`.safeio`) and the manifest of what auvplan wrote in a folder (:mod:`.manifest`)."""

__all__: list[str] = []
