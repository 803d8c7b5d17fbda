"""The ensemble fields of a results folder (``ensemble.json``): written by ``plan --out`` and ``run --out``,
read by ``report`` (issue 39)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

__all__ = ["ENSEMBLE_FILE", "write_ensemble", "read_ensemble"]

ENSEMBLE_FILE = "ensemble.json"
"""The results folder's ensemble fields (``plan --out``, ``run --out``), read by ``report``."""


def write_ensemble(out: Path, fields: dict[str, Any]) -> None:
    """Write the ensemble fields into ``out/ensemble.json`` (infinite times as null); remove a stale one
    when there are none.

    Parameters
    ----------
    out : pathlib.Path
        The results folder (prepared by the command: the name is one of its files).
    fields : dict
        The ``plan --json`` ensemble fields, or empty.
    """
    from ..files.safeio import atomic_write

    path = Path(out) / ENSEMBLE_FILE
    if not fields:
        if path.is_file() and not path.is_symlink():
            path.unlink()
        return

    def clean(v: Any) -> Any:
        if isinstance(v, dict):
            return {k: clean(x) for k, x in v.items()}
        if isinstance(v, list | tuple):
            return [clean(x) for x in v]
        if isinstance(v, float) and not math.isfinite(v):
            return None
        return v

    atomic_write(path, json.dumps(clean(fields), indent=1) + "\n")


def read_ensemble(out: Path) -> dict[str, Any] | None:
    """The ensemble fields of a results folder (``ensemble.json``), if it has them.

    Parameters
    ----------
    out : pathlib.Path
        The results folder.

    Returns
    -------
    dict or None
        The fields; None without the file (or when it is not a JSON object).
    """
    path = Path(out) / ENSEMBLE_FILE
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) else None
