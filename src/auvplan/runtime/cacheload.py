"""Loading a kernel from numba's disk cache without loading numba's compiler registries (issue 56).

numba's ``Cache.load_overload`` starts with ``target_context.refresh()``: it imports and installs every
typing and lowering registry of numba (``numba.np.*``, ``numba.cpython.*``, ``numba.typed.*`` …; ~0.2 s of
CPU) before it reads the machine code of a cached kernel, although running that code needs none of them:
the registries are what the *compiler* looks implementations up in.  The refresh was added (numba PR #2202,
issue #2198) because a cached kernel ran before numba's runtime (NRT: the allocator and reference counts of
arrays) was initialised, and crashed.  :func:`load_overload` loads a cached auvplan kernel after
initialising only that runtime, and the registries are loaded when something is compiled (numba's compiler
refreshes both contexts itself, so a cache miss is compiled exactly as before).

What a cached kernel's machine code needs at run time, and where it comes from:

* numba's C helpers (``numba_*``: math, exceptions, unicode, the random state, BLAS through SciPy's
  ``cython_blas`` imported by the helper at its first call) and ``_Py_NoneStruct``/``PyExc_*``: put into
  LLVM's symbol table when the target context is made (``BaseContext.__init__``), not by the refresh;
* NRT's functions (``NRT_*``): :func:`numba.core.runtime.rtsys.initialize`, called here;
* its environment (module globals, constants of exceptions) and the environments it references: rebuilt
  by ``CompileResult._rebuild`` from the cache file, as before;
* the one symbol a registry adds when imported: the hash secret of ``numba.cpython.hashing``
  (``_numba_hashsecret_*``, read when a kernel hashes).

The load is deferred only when all of this is checked (:func:`deferrable`): the kernel is nopython code
with no lifted loops, no objmode and no parfors re-initialisation, and every symbol its machine code leaves
undefined (read from the object file's symbol table) is already resolvable, exactly what LLVM's linker will
look up when it loads the code (without numba's runtime initialised, ``NRT_*`` are not, and the check sends
the kernel to the full refresh: no crash, only no saving); anything else takes
numba's full refresh first, as does every load once the registries are in (a compile happened).  It is
switched on only for the numba versions it was tested with (:data:`TESTED`) and off with
``AUVPLAN_NUMBA_REFRESH=1`` (numba's own behaviour).  Measured: ``plan flow-ellipsoid --json`` 0.99 → 0.84 s of
CPU (8 interleaved pairs, load 7), the JSON identical; the kernels' tests with a warm cache load all 49 of
their kernels this way and pass (``docs/performance.md``).
"""

from __future__ import annotations

import os
import struct
from typing import Any

__all__ = ["ENV_VAR", "STATS", "TESTED", "deferrable", "enabled", "load_overload", "use_deferred"]

ENV_VAR = "AUVPLAN_NUMBA_REFRESH"
"""Set to ``1`` to have every cached kernel loaded numba's way (full refresh first)."""

TESTED = ((0, 68), (0, 68))
"""numba versions (major, minor), first and last inclusive, whose cache loading this was checked against."""

STATS = {"deferred": 0, "refreshed": 0}
"""Cached kernels loaded in this process without the registries, and loaded after numba's full refresh."""


def enabled() -> bool:
    """Whether cached kernels may be loaded without numba's registries in this process.

    Returns
    -------
    bool
        False when ``AUVPLAN_NUMBA_REFRESH`` is set to anything but ``0``/empty, or numba's version is
        outside :data:`TESTED`.
    """
    if os.environ.get(ENV_VAR, "") not in ("", "0"):
        return False
    import numba

    try:
        version = tuple(int(p) for p in numba.__version__.split(".")[:2])
    except ValueError:
        return False
    return TESTED[0] <= version <= TESTED[1]


def _registries_loaded(target_context: Any) -> bool:
    from numba.core.imputils import builtin_registry

    return builtin_registry in getattr(target_context, "_registries", {builtin_registry: None})


def _declared_symbols(bitcode: bytes) -> list[str]:
    """Names the module declares but does not define (functions and globals), LLVM's intrinsics aside."""
    import llvmlite.binding as ll  # type: ignore[import-untyped]

    module = ll.parse_bitcode(bitcode)
    return [g.name for group in (module.functions, module.global_variables) for g in group
            if g.is_declaration and not g.name.startswith("llvm.")]


def _elf_undefined(obj: bytes) -> list[str] | None:
    """The undefined symbols of a 64-bit little-endian ELF object (what the JIT linker must resolve), read from
    its symbol table (~50 µs a kernel, against ~3 ms for parsing the bitcode); None for any other format."""
    if obj[:4] != b"\x7fELF" or obj[4:6] != b"\x02\x01":
        return None
    (shoff,) = struct.unpack_from("<Q", obj, 0x28)
    shentsize, shnum = struct.unpack_from("<HH", obj, 0x3A)
    sections = [struct.unpack_from("<IIQQQQIIQQ", obj, shoff + i * shentsize) for i in range(shnum)]
    names = []
    for _, kind, _, _, offset, size, link, _, _, _ in sections:
        if kind != 2:  # SHT_SYMTAB
            continue
        strings = sections[link][4]
        for st_name, _, _, shndx, _, _ in struct.iter_unpack("<IBBHQQ", obj[offset:offset + size]):
            if shndx == 0 and st_name:  # SHN_UNDEF, named
                start = strings + st_name
                names.append(obj[start:obj.index(b"\0", start)].decode())
    return names


def deferrable(payload: tuple[Any, ...], target_context: Any) -> bool:
    """Whether a cached kernel can run without numba's registries (see the module's notes).

    Parameters
    ----------
    payload : tuple
        What numba's cache file holds for one signature (``CompileResult._reduce``: library data, function
        descriptor, environment, signature, objectmode, lifted, type annotation, reload_init, environments).
    target_context : numba.core.cpu.CPUContext
        The context the kernel is loaded into.

    Returns
    -------
    bool
        True when the kernel is nopython code with nothing lifted or re-initialised, its library is object
        code with its bitcode, and every symbol its object code leaves undefined (ELF; on other formats every
        symbol its bitcode declares) resolves now (LLVM's symbol table, the process, or a library already in
        numba's engine).
    """
    import llvmlite.binding as ll

    try:
        libdata, _, _, _, objectmode, lifted, _, reload_init, _ = payload
        _, kind, (obj, bitcode) = libdata
    except (TypeError, ValueError):
        return False
    if objectmode or lifted or reload_init or kind != "object":
        return False
    try:
        needed = _elf_undefined(bytes(obj))
    except (struct.error, ValueError, IndexError, UnicodeDecodeError):  # not an object file numba wrote
        return False
    defined: set[str] = getattr(getattr(target_context.codegen(), "_engine", None), "_defined_symbols", set())
    unresolved = ".numba.unresolved$"  # numba's own late binding (recursion), resolved by its linker
    return all(name in defined or name.startswith(unresolved) or ll.address_of_symbol(name)
               for name in (_declared_symbols(bitcode) if needed is None else needed))


def load_overload(cache: Any, sig: Any, target_context: Any) -> Any:
    """Load a cached kernel as numba's ``Cache.load_overload``, the refresh deferred when :func:`deferrable`.

    Parameters
    ----------
    cache : numba.core.caching.Cache
        The kernel's cache.
    sig : tuple or Signature
        The argument types looked up.
    target_context : numba.core.cpu.CPUContext
        The context to load into.

    Returns
    -------
    numba.core.compiler.CompileResult or None
        The cached kernel, or None on a miss (numba then compiles, refreshing both contexts).
    """
    from numba.core.runtime.nrt import rtsys

    rtsys.initialize(target_context)  # the runtime cached code needs (numba issue #2198), idempotent
    with cache._guard_against_spurious_io_errors():
        if not cache._enabled:
            return None
        data = cache._cache_file.load(cache._index_key(sig, target_context.codegen()))
        if data is None:
            return None
        if deferrable(data, target_context):
            STATS["deferred"] += 1
        else:
            target_context.refresh()
            STATS["refreshed"] += 1
        return cache._impl.rebuild(target_context, data)
    return None  # pragma: no cover - an I/O error swallowed on Windows (numba's own guard)


def use_deferred(target_context: Any) -> bool:
    """Whether the next load may skip numba's refresh.

    Parameters
    ----------
    target_context : numba.core.cpu.CPUContext
        The context to load into.

    Returns
    -------
    bool
        :func:`enabled`, and numba's registries not installed yet (after a compile they are, and the refresh
        costs nothing: numba's own load is used).
    """
    return enabled() and not _registries_loaded(target_context)
