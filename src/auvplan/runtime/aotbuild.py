"""``auvplan kernels build``: the kernels numba has compiled here, compiled once more into one C extension (issue 56).

Every signature numba's on-disk cache holds for the current sources and this CPU (each kernel's index, read
through :func:`auvplan.runtime.jit._stamped_cache`: a signature compiled by any command run before) is compiled
by ``numba.pycc`` into an extension module that needs numpy alone at import (:mod:`auvplan.runtime.aot` binds
it at a kernel's call).  To give the JIT's bits, each kernel is compiled with its own numba options (its
dispatcher's: ``error_model``, ``fastmath``, ``nogil`` …, where pycc would use numba's defaults) for the host's
CPU name *and features* (pycc's default is a generic CPU; ``cpu_name="host"`` alone takes the model's features,
not the ones numba's JIT reads from LLVM).  Signatures whose argument types :func:`auvplan.runtime.aot.arg_key`
cannot express (literals, omitted arguments, records, lists …) are left to numba.

The module is written under an exclusive ``flock`` of the folder's ``.lock`` file, built in a temporary folder
beside it and moved into place with ``os.replace`` (the module first, then its manifest: a process reading
between the two finds a manifest whose functions are named by their kernel and types, so an older manifest
names either the same function or none).  A module that already holds every signature is left as it is; in the
package's own folder, the modules of older sources (and this Python) are removed.
A build that cannot be done (no C compiler, Python's headers missing, a kernel pycc refuses) raises
:class:`BuildError` with one line: the kernels then run through numba as before.
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import importlib
import importlib.machinery
import json
import os
import shutil
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from . import aot, jit

__all__ = ["Built", "BuildError", "build", "signatures", "type_key"]


class BuildError(RuntimeError):
    """The ahead-of-time module could not be built (the one-line reason is the message)."""


@dataclasses.dataclass(frozen=True)
class Built:
    """What :func:`build` did.

    Attributes
    ----------
    path : pathlib.Path
        The extension module.
    kernels : int
        Kernels with at least one signature in it.
    signatures : int
        Signatures compiled into it.
    skipped : int
        Signatures in numba's cache whose types it cannot bind (left to numba).
    seconds : float
        Wall time of the build (0 when the module was up to date).
    """

    path: Path
    kernels: int
    signatures: int
    skipped: int
    seconds: float


def type_key(t: Any) -> Any:
    """The built key of a numba type (the manifest's form, :func:`auvplan.runtime.aot.runtime_key`).

    Parameters
    ----------
    t : numba.core.types.Type
        An argument type of a compiled signature.

    Returns
    -------
    str, list or None
        ``[dtype str, ndim, layout, writeable, aligned]`` for an array of booleans or numbers, ``["(", key, …]``
        for a tuple, numba's name for a boolean or number; None for a type the binding does not express (literals,
        omitted arguments, records, lists …: never built).
    """
    from numba.core import types
    from numba.np import numpy_support

    if type(t) is types.Array:
        try:
            dtype = numpy_support.as_dtype(t.dtype)
        except (NotImplementedError, TypeError):
            return None
        if dtype.kind not in "biufc" or not t.aligned:  # numba.typeof's arrays are aligned (also when not)
            return None
        return [dtype.str, t.ndim, t.layout, bool(t.mutable), bool(t.aligned)]
    if type(t) in (types.Integer, types.Float, types.Boolean, types.Complex):
        return str(t)
    if type(t) in (types.Tuple, types.UniTuple):
        parts = [type_key(e) for e in t.types]
        return None if None in parts else ["(", *parts]
    return None


def _kernel_modules(package: str) -> list[str]:
    """The modules of ``package`` whose source defines kernels (uses the ``kernel`` decorator), imported."""
    top = importlib.import_module(package)
    root = Path(top.__file__ or ".").parent
    names = []
    for path in sorted(root.rglob("*.py")):
        if "__pycache__" in path.parts or b"@" + b"kernel" not in path.read_bytes():  # (so this file is not one)
            continue
        rel = path.relative_to(root).with_suffix("")
        parts = [package, *rel.parts]
        if parts[-1] == "__init__":
            parts.pop()
        names.append(".".join(parts))
    for name in names:
        importlib.import_module(name)
    return names


def _dispatchers(package: str) -> list[Any]:
    """Every kernel of ``package`` as its numba dispatcher (each made, :func:`auvplan.runtime.jit._make_all`)."""
    from numba.core.registry import CPUDispatcher

    modules = _kernel_modules(package)
    jit._make_all()
    found: dict[int, Any] = {}
    for name in modules:
        for value in vars(sys.modules[name]).values():
            if isinstance(value, CPUDispatcher) and value.py_func.__module__.split(".")[0] == package:
                found.setdefault(id(value), value)
    return sorted(found.values(), key=lambda d: (d.py_func.__module__, d.py_func.__qualname__))


def signatures(dispatcher: Any) -> list[tuple[Any, ...]]:
    """The argument types of every signature of ``dispatcher`` in numba's on-disk cache, current for its sources
    (:func:`auvplan.runtime.jit.source_stamp`), its bytecode and this CPU.

    Parameters
    ----------
    dispatcher : numba.core.registry.CPUDispatcher
        A kernel's dispatcher.

    Returns
    -------
    list of tuple
        numba types, one tuple a signature, in a stable order.
    """
    cache = jit._stamped_cache(dispatcher)
    codegen = dispatcher.targetdescr.target_context.codegen()
    index = cache._cache_file._load_index()
    sigs = [key[0] for key in index if cache._index_key(key[0], codegen) == key]
    return sorted(sigs, key=str)


@contextlib.contextmanager
def _locked(path: Path) -> Iterator[None]:
    import fcntl

    fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o666)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)


def _symbol(qualified: str, keys: list[Any]) -> str:
    """A compiled function's name in the module: its kernel and types hashed (never reused for another)."""
    return "k_" + hashlib.sha256((qualified + "\0" + json.dumps(keys)).encode()).hexdigest()[:24]


def _compiler_class() -> Any:
    """pycc's ``CC`` compiling each kernel with its dispatcher's options for the host's CPU and features."""
    codegen: Any = importlib.import_module("numba.core.codegen")  # numba's untyped modules, as Any
    compiler: Any = importlib.import_module("numba.core.compiler")
    registry: Any = importlib.import_module("numba.core.registry")
    pycc: Any = importlib.import_module("numba.pycc.compiler")
    cc_module: Any = importlib.import_module("numba.pycc.cc")

    class HostCodegen(codegen.AOTCPUCodegen):  # type: ignore[misc]
        def _customize_tm_features(self) -> str:
            return str(self._get_host_cpu_features())  # the JIT's features (pycc's: the CPU model's)

    class HostModuleCompiler(pycc.ModuleCompiler):  # type: ignore[misc]
        def __init__(self, entries: Any, name: str, use_nrt: bool, options: dict[int, Any]) -> None:
            super().__init__(entries, name, use_nrt, cpu_name="host")
            self.context = registry.cpu_target.target_context.subtarget(
                _internal_codegen=HostCodegen(name, cpu_name="host"), aot_mode=True)
            self._options = options

        def _cull_exports(self) -> Any:
            original = pycc.compile_extra
            options = self._options

            def compile_extra(typing: Any, target: Any, func: Any, args: Any, return_type: Any, flags: Any,
                              locals: Any, library: Any) -> Any:
                dispatcher = options[id(func)]
                own: Any = compiler.Flags()  # the dispatcher's, as numba's JIT makes them (Dispatcher._compile_core)
                dispatcher.targetdescr.options.parse_as_flags(own, dispatcher.targetoptions)
                own.no_compile, own.nrt = flags.no_compile, flags.nrt
                return original(typing, target, func, args, return_type, own, locals=dispatcher.locals,
                                library=library)

            pycc.compile_extra = compile_extra
            try:
                return super()._cull_exports()
            finally:
                pycc.compile_extra = original

    class HostCC(cc_module.CC):  # type: ignore[misc]
        options: dict[int, Any] = {}

        def _compile_object_files(self, build_dir: str) -> Any:
            module_compiler = HostModuleCompiler(self._export_entries, self._basename, self._use_nrt, self.options)
            module_compiler.external_init_function = self._init_function
            temp_obj = os.path.join(build_dir, os.path.splitext(self._output_file)[0] + ".o")
            module_compiler.write_native_object(temp_obj, wrap=True)
            return [temp_obj], module_compiler.dll_exports

    return HostCC


def _plan(dispatchers: list[Any]) -> tuple[dict[str, list[tuple[str, list[Any], Any, Any]]], int]:
    """``{"module:qualname": [(symbol, keys, signature, dispatcher)]}`` of every bindable cached signature, and
    the number skipped."""
    plan: dict[str, list[tuple[str, list[Any], Any, Any]]] = {}
    skipped = 0
    for d in dispatchers:
        qualified = f"{d.py_func.__module__}:{d.py_func.__qualname__}"
        for sig in signatures(d):
            keys = [type_key(t) for t in sig]
            if None in keys:
                skipped += 1
                continue
            plan.setdefault(qualified, []).append((_symbol(qualified, keys), keys, sig, d))
    return plan, skipped


def build(package: str = "auvplan", where: Path | None = None) -> Built:
    """Compile every cached signature of ``package``'s kernels into its ahead-of-time module.

    Parameters
    ----------
    package : str
        The top-level package whose kernels are built.
    where : pathlib.Path, optional
        The folder (default :func:`auvplan.runtime.aot.folder` of the package).

    Returns
    -------
    Built
        The module and its counts.

    Raises
    ------
    BuildError
        Kernels run as plain Python, nothing cached to build, or the compile or link failed (one line).
    """
    if not jit.jit_enabled():
        raise BuildError("NUMBA_DISABLE_JIT is set: the kernels run as plain Python")
    t0 = time.monotonic()
    root = str(Path(importlib.import_module(package).__file__ or ".").resolve().parent)
    plan, skipped = _plan(_dispatchers(package))
    if not plan:
        raise BuildError("numba's cache holds no kernel for the current sources yet: run a command first")
    stamp = jit.source_stamp(root)
    name = aot.module_name(stamp)
    folder = where if where is not None else aot.folder(root)
    manifest = {"key": aot.build_key(stamp),
                "kernels": {q: [[sym, keys] for sym, keys, _, _ in entries] for q, entries in sorted(plan.items())}}
    path = folder / (name + importlib.machinery.EXTENSION_SUFFIXES[0])
    count = sum(len(e) for e in plan.values())
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with _locked(folder / (aot.PREFIX + "build.lock")):
            if where is None:
                _remove_stale(folder, name)
            with contextlib.suppress(OSError, ValueError):
                old = json.loads((folder / (name + ".json")).read_text(encoding="utf-8"))
                if old == manifest and path.is_file():
                    return Built(path, len(plan), count, skipped, 0.0)
            _compile(plan, name, folder, manifest)
    except BuildError:
        raise
    except Exception as exc:  # noqa: BLE001 - a compiler or toolchain failure of any kind: numba, as before
        text = " ".join(str(exc).split()) or type(exc).__name__
        raise BuildError(f"{type(exc).__name__}: {text[:300]}") from exc
    return Built(path, len(plan), count, skipped, time.monotonic() - t0)


def _remove_stale(folder: Path, name: str) -> None:
    """Remove the modules of older sources (this Python's, another name) from the package's own folder, with their
    manifests: never found again (their names hash other stamps), ~1.5 MB each."""
    suffix = importlib.machinery.EXTENSION_SUFFIXES[0]
    for path in folder.glob(aot.PREFIX + "*" + suffix):
        old = path.name[: -len(suffix)]
        if old != name:
            for stale in (path, folder / (old + ".json")):
                with contextlib.suppress(OSError):
                    stale.unlink()


def _compile(plan: dict[str, list[tuple[str, list[Any], Any, Any]]], name: str, folder: Path,
             manifest: dict[str, Any]) -> None:
    """Build the module in a temporary folder beside ``folder``'s, then move it and its manifest into place."""
    typing: Any = importlib.import_module("numba.core.typing")
    cc_class = _compiler_class()
    tmp = Path(tempfile.mkdtemp(prefix=name + ".", dir=folder))
    try:
        cc = cc_class(name, source_module=sys.modules[__name__])
        cc.output_dir = str(tmp)
        cc.options = {}
        for entries in plan.values():
            for symbol, _, sig, dispatcher in entries:
                cc.options[id(dispatcher.py_func)] = dispatcher
                cc._exported_functions[symbol] = _entry(symbol, typing.signature(None, *sig), dispatcher.py_func)
        with contextlib.redirect_stdout(sys.stderr):  # the toolchain's chatter, never on stdout
            cc.compile()
        built = tmp / cc.output_file
        (tmp / "manifest.json").write_text(json.dumps(manifest, indent=1), encoding="utf-8")
        os.replace(built, folder / (name + importlib.machinery.EXTENSION_SUFFIXES[0]))
        os.replace(tmp / "manifest.json", folder / (name + ".json"))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def _entry(symbol: str, sig: Any, func: Any) -> Any:
    pycc: Any = importlib.import_module("numba.pycc.compiler")
    return pycc.ExportEntry(symbol, sig, func)
