"""Kernels compiled ahead of time: an extension module that runs them without importing numba (issue 56).

A command's first kernel call cost numba's import (~0.2 s of CPU) and the load of its cached kernels with numba's
runtime (~0.15 s), over the 0.5 s issue 56 allows the front door.  ``auvplan kernels build``
(:mod:`auvplan.runtime.aotbuild`) compiles every kernel signature numba's on-disk cache holds for the current
sources into one C extension (``numba.pycc``: numpy alone at import, ~0.3 ms), with each kernel's own numba
options and the host's CPU and features, so that its machine code computes the same bits as the JIT's.  At a
kernel's call, before numba is imported (:class:`auvplan.runtime.jit._Deferred`), :func:`table` gives the
compiled functions of that kernel keyed on their argument types, and :func:`args_key` the key of the call's
arguments as numba would type them (:func:`arg_key`: dtype, dimensions, layout and writeable of an array;
the numba type of a scalar; a tuple element by element): an exact match runs the compiled function, and anything
else — a type never built, a keyword argument, a value numba would type otherwise (a Python int past
int64, an ndarray subclass) — goes to numba as before.  Nothing is ever converted.

**Never stale.**  The module's name hashes :func:`build_key`: the kernels' :func:`~auvplan.runtime.jit.source_stamp`
(any edit of a kernel file gives a new name, so an old module is never found), the numba, llvmlite, numpy and
Python it was built with, the CPU (``/proc/cpuinfo``) and every ``NUMBA_*`` setting of the environment; the
manifest beside it repeats the full key and is compared.  ``AUVPLAN_AOT=0`` (the test suite's default) or
``NUMBA_DISABLE_JIT=1`` never use it; a module missing, half written or failing to load means numba, as before.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.machinery
import importlib.util
import json
import os
import platform
import sys
import threading
from pathlib import Path
from typing import Any

__all__ = ["DIR_VAR", "ENV_VAR", "MISSES", "PREFIX", "arg_key", "args_key", "build_key", "enabled", "folder",
           "module_name", "runtime_key", "table"]

ENV_VAR = "AUVPLAN_AOT"
"""Set to ``0`` to run every kernel through numba (no ahead-of-time module is looked for)."""

DIR_VAR = "AUVPLAN_AOT_DIR"
"""The folder of the built modules, when set (else :func:`folder`'s default)."""

MISSES: list[str] = []
"""Kernels (``module:qualname``) called in this process, a module being built, that it lacks, or with argument
types it lacks, or with keywords: numba was used from then on (what ``tools/identity_dump.py`` and the tests
read)."""

PREFIX = "_auvplan_kernels_"
"""The start of a built module's name (then 20 hex digits of :func:`build_key`'s hash)."""

_SCALARS: dict[type, str] = {}
"""numba's type of a Python or numpy scalar, by its exact class (filled in at first use)."""

_ARRAY: list[type] = []
"""``numpy.ndarray`` (set at first use: this module is imported before numpy may be)."""


def enabled() -> bool:
    """Whether ahead-of-time kernels may be used in this process.

    Returns
    -------
    bool
        False when ``AUVPLAN_AOT`` is ``0`` or the kernels run as plain Python (``NUMBA_DISABLE_JIT``).
    """
    if os.environ.get(ENV_VAR, "").strip() == "0":
        return False
    from .jit import jit_enabled

    return jit_enabled()


def _numpy_scalars() -> dict[type, str]:
    if not _SCALARS:
        import numpy as np

        _SCALARS.update({float: "float64", int: "int64", bool: "bool", complex: "complex128"})
        for t in (np.float64, np.float32, np.int64, np.int32, np.int16, np.int8, np.uint64, np.uint32, np.uint16,
                  np.uint8, np.complex128, np.complex64):
            _SCALARS[t] = np.dtype(t).name
        _SCALARS[np.bool_] = "bool"
        _ARRAY.append(np.ndarray)
    return _SCALARS


def _key_into(value: Any, out: list[Any], canonical: bool) -> bool:
    """Append :func:`arg_key`'s parts of ``value`` to ``out``; False for a value of no known type."""
    t = type(value)
    scalars = _SCALARS or _numpy_scalars()
    if t is _ARRAY[0]:
        n = value.flags.num  # numpy's flag bits: 1 C-, 2 F-contiguous, 0x400 writeable
        dtype = _CANONICAL.get(value.dtype) if canonical else value.dtype
        out.append(id(dtype))
        out.append(value.ndim << 16 | n & 0x400 | (1 if n & 1 else n & 2))
        return True
    name = scalars.get(t)
    if name is not None:
        if t is int and not -(2**63) <= value < 2**63:  # numba types it uint64 or refuses it
            return False
        out.append(name)
        return True
    if t is tuple:
        out.append("(")
        ok = all([_key_into(v, out, canonical) for v in value])
        out.append(")")
        return ok
    return False


def arg_key(value: Any, canonical: bool = False) -> tuple[Any, ...] | None:
    """The key of one argument: numba's type of it (``numba.typeof``), as :func:`runtime_key` gives a built one.

    Parameters
    ----------
    value : object
        An argument of a kernel's call.
    canonical : bool
        Name an array's dtype by numpy's own object for it (found by equality, byte order included) rather than
        by the array's dtype object: an equal copy (an unpickled array's) then matches too.

    Returns
    -------
    tuple or None
        For a ``numpy.ndarray`` (exactly): the identity of its dtype object (numpy's dtypes of numbers are one
        object each, so another object never matches) and ``ndim << 16 | flags | layout``, layout 1 for
        C-contiguous (also when F-contiguous too, as numba types it), 2 for F-contiguous, 0 for any, flags the
        writeable bit (0x400; numba's type of an array is read-only or not, and always aligned).  For a scalar
        numba's type name (``"float64"``, ``"int64"``, ``"bool"`` …).  For a tuple its elements' keys between
        ``"("`` and ``")"``.  None for a value of no known type or a Python int past int64 (numba types it uint64):
        never matched.
    """
    out: list[Any] = []
    return tuple(out) if _key_into(value, out, canonical) else None


def args_key(args: tuple[Any, ...], canonical: bool = False) -> tuple[Any, ...] | None:
    """The key of a call's positional arguments: their :func:`arg_key` parts, one after the other.

    Parameters
    ----------
    args : tuple
        A call's positional arguments.
    canonical : bool
        As :func:`arg_key`'s (the second look-up, after the fast one missed).

    Returns
    -------
    tuple or None
        The key (arrays give two ints, scalars a name, tuples their parts between parentheses: never ambiguous),
        or None when an argument has no known type.
    """
    array = _ARRAY[0] if _ARRAY else _numpy_scalars() and _ARRAY[0]
    out: list[Any] = []
    for v in args:  # _key_into with its two commonest cases inlined (a kernel call's overhead)
        t = type(v)
        if t is array and not canonical:
            n = v.flags.num
            out.append(id(v.dtype))
            out.append(v.ndim << 16 | n & 0x400 | (1 if n & 1 else n & 2))
        elif t is float:
            out.append("float64")
        elif not _key_into(v, out, canonical):
            return None
    return tuple(out)


_LAYOUTS = {"C": 1, "F": 2, "A": 0}

_CANONICAL: dict[Any, Any] = {}
"""numpy's dtype object of each dtype a built module names (an equal dtype object maps to it)."""


def runtime_key(built: list[Any]) -> tuple[Any, ...]:
    """The :func:`args_key` of a call whose numba types are a built signature's (the manifest's keys).

    Parameters
    ----------
    built : list
        One key an argument (:func:`auvplan.runtime.aotbuild.type_key`): ``[dtype str, ndim, layout "C"|"F"|"A",
        writeable, aligned]`` for an array, ``["(", key, …]`` for a tuple, numba's name for a scalar.

    Returns
    -------
    tuple
        The key compared with :func:`args_key`'s.

    Raises
    ------
    ValueError
        For a key of no known form.
    """
    import numpy as np

    out: list[Any] = []

    def add(key: Any) -> None:
        if isinstance(key, str):
            out.append(key)
        elif key and key[0] == "(":
            out.append("(")
            for k in key[1:]:
                add(k)
            out.append(")")
        elif len(key) == 5:
            dtype_str, ndim, layout, writeable, aligned = key
            if not aligned:  # numba.typeof never gives it: no call is of this type
                raise ValueError(f"unaligned array key {key!r}")
            dtype = _CANONICAL.setdefault(np.dtype(dtype_str), np.dtype(dtype_str))
            out.append(id(dtype))
            out.append(int(ndim) << 16 | (0x400 if writeable else 0) | _LAYOUTS[layout])
        else:
            raise ValueError(f"unknown argument key {key!r}")

    for k in built:
        add(k)
    return tuple(out)


def _version_file(package: str) -> str:
    """The text of an installed package's ``_version.py`` (found, not imported), or its folder's name."""
    try:
        spec = importlib.util.find_spec(package)
    except (ImportError, ValueError):
        return ""
    origin: str | None = getattr(spec, "origin", None)
    if not origin:
        return ""
    try:
        return Path(origin).with_name("_version.py").read_text(encoding="utf-8", errors="replace")
    except OSError:
        return origin


def _cpu() -> str:
    """The first processor's model and flags (``/proc/cpuinfo``), else :func:`platform.processor`."""
    parts: list[str] = []
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as fh:
            for line in fh:
                if not line.strip() and parts:
                    break
                if line.split(":", 1)[0].strip() in ("model name", "flags", "Features", "CPU implementer",
                                                      "CPU part"):
                    parts.append(" ".join(line.split()))
    except OSError:
        parts.append(platform.processor())
    return "\n".join(parts)


@functools.cache
def build_key(stamp: str) -> str:
    """What a built module is valid for (hashed into its name, repeated in full in its manifest).

    Parameters
    ----------
    stamp : str
        The kernels' source stamp (:func:`auvplan.runtime.jit.source_stamp` of their package).

    Returns
    -------
    str
        The stamp, Python's version and extension suffix, numpy's version, numba's and llvmlite's version files,
        the machine and CPU, and every ``NUMBA_*`` variable of the environment but the cache folder.
    """
    import numpy as np

    numba_env = sorted(f"{k}={v}" for k, v in os.environ.items() if k.startswith("NUMBA_") and k != "NUMBA_CACHE_DIR")
    parts = [stamp, sys.version, importlib.machinery.EXTENSION_SUFFIXES[0], np.__version__,
             hashlib.sha256(_version_file("numba").encode()).hexdigest(),
             hashlib.sha256(_version_file("llvmlite").encode()).hexdigest(),
             platform.machine(), _cpu(), *numba_env]
    return "\n".join(parts)


def module_name(stamp: str) -> str:
    """The built module's name for kernels of ``stamp`` on this machine (:data:`PREFIX` + 20 hex digits).

    Parameters
    ----------
    stamp : str
        The kernels' source stamp.

    Returns
    -------
    str
        A valid Python module name.
    """
    return PREFIX + hashlib.sha256(build_key(stamp).encode()).hexdigest()[:20]


def folder(root: str) -> Path:
    """Where the built module of the package at ``root`` lives.

    Parameters
    ----------
    root : str
        The package's folder.

    Returns
    -------
    pathlib.Path
        ``$AUVPLAN_AOT_DIR`` when set; else the package's ``__pycache__`` when it can be written (where numba's
        cache of the kernels is); else ``$XDG_CACHE_HOME/auvplan/kernels`` (``~/.cache``).
    """
    chosen = os.environ.get(DIR_VAR, "").strip()
    if chosen:
        return Path(chosen)
    here = Path(root) / "__pycache__"
    if os.access(here if here.is_dir() else Path(root), os.W_OK):
        return here
    base = os.environ.get("XDG_CACHE_HOME", "").strip() or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "auvplan" / "kernels"


_TABLES: dict[str, dict[str, dict[tuple[Any, ...], Any]]] = {}
_LOCK = threading.Lock()


def table(root: str) -> dict[str, dict[tuple[Any, ...], Any]]:
    """The ahead-of-time kernels of the package at ``root``: ``{"module:qualname": {args key: function}}``.

    Parameters
    ----------
    root : str
        The package's folder (its kernels' :func:`~auvplan.runtime.jit.source_stamp`).

    Returns
    -------
    dict
        Empty when not :func:`enabled`, or no module is built for the current sources and machine, or its manifest
        does not repeat :func:`build_key`, or it does not load; read once a process and package.
    """
    got = _TABLES.get(root)
    if got is not None:
        return got
    with _LOCK:
        if root not in _TABLES:
            _TABLES[root] = _load(root) if enabled() else {}
        return _TABLES[root]


def _load(root: str) -> dict[str, dict[tuple[Any, ...], Any]]:
    from .jit import source_stamp

    stamp = source_stamp(root)
    name = module_name(stamp)
    where = folder(root)
    path = where / (name + importlib.machinery.EXTENSION_SUFFIXES[0])
    try:
        manifest = json.loads((where / (name + ".json")).read_text(encoding="utf-8"))
        if manifest.get("key") != build_key(stamp) or not path.is_file():
            return {}
        loader = importlib.machinery.ExtensionFileLoader(name, str(path))
        spec = importlib.util.spec_from_file_location(name, str(path), loader=loader)
        if spec is None:  # pragma: no cover - a path with an extension suffix always has a spec
            return {}
        module = importlib.util.module_from_spec(spec)
        loader.exec_module(module)
        out: dict[str, dict[tuple[Any, ...], Any]] = {}
        for qualified, entries in manifest["kernels"].items():
            out[qualified] = {runtime_key(keys): getattr(module, symbol) for symbol, keys in entries}
        return out
    except (OSError, ValueError, KeyError, TypeError, AttributeError, ImportError):
        return {}  # nothing built here, or not readable: numba, as before
