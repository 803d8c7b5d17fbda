"""Vector features read once: the local-frame geometries a vector reader made, kept in the readers' cache.

Reading a coastline or a chart's zones (pyogrio, which brings pandas in, then densify, project and clip) costs
a few tenths of a second of every ``validate`` and ``plan`` of the scenario while the result is a few kilobytes
of polygons (issue 56).  :func:`kept_geometries` keeps that result in :mod:`auvplan.io.data.cache` as
well-known binary, which stores every coordinate as the float64 it is: a kept geometry is the computed one,
vertex for vertex.  The key holds every file of the data set (a shapefile's ``.shp`` with its ``.dbf``,
``.prj`` …: every file of the folder named ``stem.*``), so editing any of them reads the data again.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import shapely

from ..cache import cached, dataset_files

__all__ = ["kept_geometries"]

Named = list[tuple[str, Any]]
"""Named local-frame geometries."""


def _pack(named: Named) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
    blobs = [shapely.to_wkb(g) for _, g in named]
    data = np.frombuffer(b"".join(blobs), dtype=np.uint8) if blobs else np.empty(0, dtype=np.uint8)
    return {"wkb": data, "ends": np.cumsum([len(b) for b in blobs], dtype=np.int64)}, {
        "names": [n for n, _ in named]}


def _unpack(arrays: dict[str, np.ndarray], record: dict[str, Any]) -> Named:
    data, ends = arrays["wkb"].tobytes(), [int(e) for e in arrays["ends"]]
    starts = [0, *ends][:len(ends)]  # none for no geometry (a file with no feature in the area)
    return [(str(n), shapely.from_wkb(data[a:b])) for n, a, b in zip(record["names"], starts, ends, strict=True)]


def kept_geometries(kind: str, request: Any, path: Path, compute: Callable[[], Named]) -> Named:
    """``compute()`` (named local-frame geometries read from ``path``), or its kept result.

    Parameters
    ----------
    kind : str
        What is kept (``"land"``, ``"zones"``): the prefix of the cache entry.
    request : object
        Everything besides the files that the result depends on (the table, the frame's origin, the
        extent); its ``repr`` must be exact.
    path : pathlib.Path
        The vector file (its sidecar files are part of the key,
        :func:`~auvplan.io.data.cache.dataset_files`).
    compute : callable
        The reader: ``() -> [(name, geometry), ...]``.

    Returns
    -------
    list of (str, shapely geometry)
        What ``compute`` returns (or returned for the same files, request and code), in its order.
    """
    return cached(kind, request, dataset_files(path), compute, _pack, _unpack)
