"""Self-contained results folders: what ``report`` and ``export`` need besides the run record.

A results folder keeps the scenario text (``scenario.toml``), where it came from
(``source.json``) and the terrain the run used, exactly as it was built (``terrain.npz``: the
cropped, resampled grid in the scenario's local frame).  ``report``/``export`` rebuild the World
from these, so the folder still works after it has been moved or the original data file is gone.
Other data references (a currents file) are resolved against the scenario's original folder.
"""

from __future__ import annotations

import io
import zipfile
from pathlib import Path
from typing import Any

import numpy as np

from ...errors import DataError
from ...world import Terrain
from ...world.seabed import SeabedFit
from ..files.jsonfile import source_base
from ..files.safeio import atomic_write

__all__ = ["TERRAIN_FILE", "save_terrain", "load_terrain", "scenario_base"]

TERRAIN_FILE = "terrain.npz"
"""The terrain cut-out saved beside the results."""


def save_terrain(out: Path, terrain: Terrain | None) -> Path | None:
    """Save ``terrain`` (axes, elevation, name) as ``out/terrain.npz``; nothing without a terrain.

    Parameters
    ----------
    out : pathlib.Path
        Results folder.
    terrain : Terrain or None
        The terrain the run used.

    Returns
    -------
    pathlib.Path or None
        The file written, or None without a terrain.
    """
    if terrain is None:
        return None
    buf = io.BytesIO()
    fit = terrain.fit
    arrays: dict[str, Any] = {"x": terrain.x, "y": terrain.y, "z": terrain.z, "name": np.array(terrain.name)}
    if fit is not None:
        arrays.update(fit_method=np.array(fit.method),
                      fit=np.array([fit.excess_max_m, fit.excess_mean_m, fit.deficit_max_m]))
    np.savez_compressed(buf, **arrays)
    return atomic_write(Path(out) / TERRAIN_FILE, buf.getvalue())


def load_terrain(out: Path) -> Terrain | None:
    """Load the terrain saved by :func:`save_terrain` in ``out``.

    Parameters
    ----------
    out : pathlib.Path
        Results folder.

    Returns
    -------
    Terrain or None
        The terrain, or None when the folder has none.

    Raises
    ------
    DataError
        When the file is unreadable or malformed (naming it).
    """
    path = Path(out) / TERRAIN_FILE
    if not path.is_file():
        return None
    try:
        with np.load(path, allow_pickle=False) as f:
            fit = SeabedFit(str(f["fit_method"]), *map(float, f["fit"])) if "fit" in f else None
            return Terrain(f["x"], f["y"], f["z"], name=str(f["name"]), fit=fit)
    except (KeyError, ValueError, OSError, EOFError, zipfile.BadZipFile) as exc:
        raise DataError(f"{path}: unreadable terrain cut-out ({exc})") from exc


def scenario_base(out: Path) -> Path:
    """Return the folder against which the stored scenario's relative data paths resolve.

    Parameters
    ----------
    out : pathlib.Path
        Results folder.

    Returns
    -------
    pathlib.Path
        The original scenario's folder recorded in ``source.json`` (followed through a results folder run
        again: :func:`auvplan.io.files.jsonfile.source_base`), or ``out`` itself.
    """
    return source_base(Path(out) / "scenario.toml")
