"""Open a NetCDF data file, diagnosing what is wrong with it when it cannot be used.

xarray reads lazily and some damage only shows when values are read (a NetCDF-3 file cut short
is read as zeros or garbage, then reported as "axes must be strictly monotonic" far away).  The
checks here tell the faults apart, each naming the file: missing, not a NetCDF/HDF5 file at all
(its first bytes), truncated (the header describes more data than the file holds), unreadable;
:func:`variable_values` reads one variable and names it when that fails.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from ...errors import DataError

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["open_dataset", "no_index", "variable_values", "check_dims"]

_CDF = (b"CDF\x01", b"CDF\x02", b"CDF\x05")
_HDF5 = b"\x89HDF\r\n\x1a\n"


def _check_classic(path: Path, size: int) -> None:
    """A NetCDF-3 (CDF-1/2) file must hold every byte its header describes."""
    from scipy.io import netcdf_file

    try:
        with netcdf_file(path, mmap=False) as nc:
            for var in nc.variables.values():
                _ = var.data.shape
    except (ValueError, TypeError, IndexError, OSError, EOFError) as exc:
        raise DataError(f"{path}: truncated or damaged NetCDF-3 file ({size} bytes; reading it fails: {exc})") \
            from exc


def _hdf5_declared_size(head: bytes) -> int | None:
    """End-of-file address stored in an HDF5 superblock (versions 0-3) at the start of the file."""
    if len(head) < 16 or head[:8] != _HDF5:
        return None
    version = head[8]
    if version in (0, 1):
        size_o = head[13]
        at = 24 + (4 if version == 1 else 0) + 2 * size_o
    elif version in (2, 3):
        size_o = head[9]
        at = 12 + 2 * size_o
    else:
        return None
    if size_o not in (2, 4, 8) or len(head) < at + size_o:
        return None
    return int.from_bytes(head[at:at + size_o], "little")


def open_dataset(path: Path, what: str, **kwargs: Any) -> xr.Dataset:
    """``xarray.open_dataset(path)`` after checking the file is there, is NetCDF/HDF5, and is whole.

    Parameters
    ----------
    path : Path
        The file.
    what : str
        What it should hold ("bathymetry", "current"), for the messages.
    **kwargs
        Passed to :func:`xarray.open_dataset`.

    Returns
    -------
    xarray.Dataset
        The open dataset (close it, or use it as a context manager).

    Raises
    ------
    DataError
        Naming the file and the fault.
    """
    path = Path(path)
    if not path.is_file():
        raise DataError(f"{path}: {what} file not found" if not path.exists() else
                        f"{path}: the {what} file is not a regular file (a FIFO, a device or a folder)")
    try:
        with path.open("rb") as fh:
            head = fh.read(96)
        size = path.stat().st_size
    except OSError as exc:
        raise DataError(f"{path}: cannot read the {what} file ({exc.strerror or exc})") from exc
    if size == 0:
        raise DataError(f"{path}: the {what} file is empty (0 bytes)")
    if head[:4] not in _CDF and head[:8] != _HDF5:
        raise DataError(f"{path}: cannot read the {what} file: not a NetCDF file (it starts with {head[:8]!r}; "
                        "NetCDF-3 starts with b'CDF', NetCDF-4 with the HDF5 signature)")
    if head[:4] in _CDF[:2]:
        _check_classic(path, size)
    declared = _hdf5_declared_size(head)
    if declared is not None and size < declared:
        raise DataError(f"{path}: truncated NetCDF-4/HDF5 file: {size} bytes of the {declared} its header declares")
    try:
        # the engine xarray would pick first for NetCDF, named: no scan of every installed backend (which
        # imports rioxarray, dask and more, about a second of a command's start)
        import xarray as xr  # imported when used (issue 56)
        from xarray.backends import NetCDF4BackendEntrypoint

        kwargs.setdefault("engine", NetCDF4BackendEntrypoint)
        return xr.open_dataset(path, **(no_index() | kwargs))
    except Exception as exc:  # xarray and the HDF5 library raise many types for damaged files
        text = " ".join(str(exc).split())
        fault = "truncated" if "truncat" in text.lower() or "eof" in text.lower() else "damaged or unreadable"
        raise DataError(f"{path}: {fault} NetCDF file ({text[:200]})") from exc


def no_index() -> dict[str, Any]:
    """``{"create_default_indexes": False}`` where xarray takes it (2025.7 and later), else ``{}``.

    The readers index by position only (``isel``, ``transpose``, numpy on ``.values``): the pandas indexes
    xarray builds for every dimension coordinate are never used, and building the first one imports dask
    and pint to test for their array types (~0.2 s of a command's start, issue 56).

    Returns
    -------
    dict
        Keyword arguments for :func:`xarray.open_dataset`.
    """
    import xarray as xr

    return {"create_default_indexes": False} if _takes_index_flag(xr.open_dataset) else {}


def _takes_index_flag(fn: Any) -> bool:
    import inspect

    return "create_default_indexes" in inspect.signature(fn).parameters


def variable_values(da: xr.DataArray, src: str) -> NDArray[np.float64]:
    """Read the values of a variable (or coordinate) as floats, naming the file and variable on failure.

    Parameters
    ----------
    da : xarray.DataArray
        The variable.
    src : str
        The file, for messages.

    Returns
    -------
    numpy.ndarray
        The values as float64, in the variable's own units.
    """
    try:
        return np.asarray(da.values, dtype=float)
    except Exception as exc:  # HDF5/netCDF read errors surface only here, lazily
        raise DataError(f"{src}: variable {str(da.name)!r} cannot be read (truncated or damaged file: "
                        f"{' '.join(str(exc).split())[:160]})") from exc


def check_dims(da: xr.DataArray, want: int, src: str, role: str) -> None:
    """Raise a DataError naming the variable when ``da`` does not have ``want`` dimensions.

    Parameters
    ----------
    da : xarray.DataArray
        The variable.
    want : int
        Number of dimensions required.
    src : str
        The file, for messages.
    role : str
        What the variable is used as ("elevation", "eastward current" …), for messages.
    """
    if da.ndim != want:
        dims = ", ".join(f"{d} = {n}" for d, n in da.sizes.items()) or "none"
        raise DataError(f"{src}: variable {da.name!r} has {da.ndim} dimension(s) ({dims}); the {role} must be "
                        f"{want}-D" + ("; select one time/level first" if da.ndim > want else ""))
