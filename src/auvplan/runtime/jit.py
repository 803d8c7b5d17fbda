"""The one way auvplan compiles its inner loops (numba).

Kernels release the GIL, raise no Python exceptions on division (``error_model="numpy"``: inf/nan
as in numpy) and allow only the floating-point liberties that cannot change which values are
finite: no signed zeros, reciprocal multiplication and fused multiply-add (no ``nnan``/``ninf``,
so ±inf margins keep working).

**The on-disk cache never serves a stale kernel.**  Numba's own ``cache=True`` stamps a cached
kernel with its *own* source file only, while a kernel that calls a kernel of another module
(the cost pass calls the terrain's elevation kernel) has that callee compiled into it: after an
edit of the callee, numba would load the old machine code for the caller.  Here every kernel's
cache entry is stamped with a hash of *every* source file of its package that defines kernels
(``@kernel``), so any edit of any kernel module recompiles every kernel once.  The cache lives
where numba would put it (``__pycache__`` beside the module, ``NUMBA_CACHE_DIR`` when set, or the
user-wide cache for read-only installs).  Should numba's internals change, caching is switched
off rather than risked (``NUMBA_DISABLE_JIT=1`` runs the kernels as plain Python).

**numba is imported when the first kernel runs, not when kernels are defined.**  ``@kernel`` returns a
stand-in; the first call of any kernel makes every kernel's dispatcher and puts each in place of its
stand-in in every module that holds it (:class:`_Deferred`), so that a command that runs no kernel —
``validate`` of a scenario whose files are cached, a start and goal well clear of the seabed — does not pay
numba's import and registries (~0.6 s of CPU, issue 56).  The dispatchers and the machine code are the
ones an eager decorator makes.  Each kernel's on-disk cache object is made at its first compile
(:class:`_CacheOnUse`: ~0.4 ms a kernel, paid before for every kernel defined), and numba's registries load
without importing ``scipy.linalg`` for their BLAS check (:class:`_BlasProbe`: the same question asked of
the installed files; ~0.1-0.2 s).  A kernel found in the disk cache is loaded without numba's typing and
lowering registries when its machine code needs nothing they add (:mod:`auvplan.runtime.cacheload`; ~0.2 s,
``AUVPLAN_NUMBA_REFRESH=1`` for numba's own load).  What is left at a kernel's first call is numba's own
floor: its import (~0.2-0.3 s) and ~3 ms a cached kernel (LLVM).

**Kernels compiled ahead of time run without numba.**  After ``auvplan kernels build`` (:mod:`auvplan.runtime.aotbuild`:
every signature numba's cache holds, compiled by ``numba.pycc`` into one C extension with the kernel's own options
for the host's CPU and features: the JIT's bits), a stand-in's call whose argument types match a built signature
exactly runs the built function (:mod:`auvplan.runtime.aot`); any other call makes the dispatchers as above.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import os
import sys
import threading
import types
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar, overload

from . import aot, cacheload

__all__ = ["jit_enabled", "kernel", "source_stamp"]

#: A function compiled by :func:`kernel`; the dispatcher is called with the same arguments.
F = TypeVar("F", bound=Callable[..., Any])

_SETTINGS: dict[str, Any] = dict(nogil=True, error_model="numpy", fastmath={"nsz", "arcp", "contract"})


def jit_enabled() -> bool:
    """Whether :func:`kernel` compiles (False under ``NUMBA_DISABLE_JIT=1``: kernels run as plain Python).

    Returns
    -------
    bool
        numba's ``DISABLE_JIT`` setting, negated.
    """
    if "numba" not in sys.modules and not os.path.exists(".numba_config.yaml"):  # numba's other source of it
        try:  # numba's own reading of the variable (any integer; unset is 0), without importing numba (issue 56)
            return not int(os.environ.get("NUMBA_DISABLE_JIT", "").strip() or 0)
        except ValueError:
            pass  # numba warns and takes its default: let it
    from numba import config

    return not bool(config.DISABLE_JIT)  # type: ignore[attr-defined]  # numba.config sets it at import


@functools.cache
def source_stamp(root: str) -> str:
    """SHA-256 over the path and text of every ``.py`` file under ``root`` that defines kernels.

    Parameters
    ----------
    root : str
        Directory of a package.

    Returns
    -------
    str
        Hex digest; computed once per process and directory.
    """
    h = hashlib.sha256()
    files = []
    for folder, dirs, names in os.walk(root):  # a third of Path.rglob's cost (~5 ms of a command's start)
        dirs[:] = [d for d in dirs if d != "__pycache__"]
        files += [os.path.relpath(os.path.join(folder, n), root) for n in names if n.endswith(".py")]
    for rel in sorted(files):
        with open(os.path.join(root, rel), "rb") as fh:
            data = fh.read()
        if b"@kernel" in data:
            h.update(rel.encode() + b"\0" + data + b"\0")
    return h.hexdigest()


def _package_root(py_func: Callable[..., Any]) -> str:
    top = sys.modules[py_func.__module__.split(".")[0]]
    file = getattr(top, "__file__", None) or sys.modules[py_func.__module__].__file__ or "."
    return str(Path(file).resolve().parent)


@functools.cache
def _cache_class(root: str) -> Any:
    """numba's ``FunctionCache`` whose source stamp is :func:`source_stamp` of ``root`` (one class a package)."""
    from numba.core import caching

    def stamped(base: Any) -> Any:
        return type("Stamped" + base.__name__, (base,), {"get_source_stamp": lambda self: source_stamp(root)})

    class KernelCacheImpl(caching.CompileResultCacheImpl):
        _locator_classes = [stamped(c) for c in (caching.UserProvidedCacheLocator, caching.InTreeCacheLocator,
                                                  caching.UserWideCacheLocator)]

    class KernelCache(caching.FunctionCache):
        _impl_class = KernelCacheImpl

        def __init__(self, py_func: Any) -> None:
            super().__init__(py_func)  # type: ignore[no-untyped-call]
            self._cache_file = _locked_file_class()(cache_path=self._cache_path,
                                                    filename_base=self._impl.filename_base,
                                                    source_stamp=self._impl.locator.get_source_stamp())

        def load_overload(self, sig: Any, target_context: Any) -> Any:  # numba's registries when compiling
            if cacheload.use_deferred(target_context):
                return cacheload.load_overload(self, sig, target_context)
            return super().load_overload(sig, target_context)  # type: ignore[no-untyped-call]

    return KernelCache


@functools.cache
def _locked_file_class() -> Any:
    """numba's ``IndexDataCacheFile`` (a kernel's index ``.nbi`` and its data files ``.N.nbc``) read and written
    under a lock of the index (``flock`` on ``.nbi.lock`` beside it: shared to read, exclusive to write).

    numba writes each file atomically but not the pair: a process that saves a signature writes the index, then
    the data file it names, so that another process compiling the same kernel at once (the suite and
    ``tests/warm_kernels.py``, two dask workers on a fresh install) could read the index between the two and
    load a data file of an older source (numbered files are reused after an edit) or another signature's, or
    two writers numbering their entries alike leave an index naming the other's machine code; and a process
    killed between the two left that index for good.  Here the data file is written first, then the index that
    names it, both under the lock.  Without a lock file (a folder it cannot be made in) they go on unlocked."""
    import fcntl
    import itertools

    from numba.core import caching

    class LockedIndexDataCacheFile(caching.IndexDataCacheFile):
        @contextlib.contextmanager
        def _locked(self, how: int) -> Any:
            try:
                fd = os.open(self._index_path + ".lock", os.O_RDWR | os.O_CREAT, 0o666)
            except OSError:
                yield
                return
            try:
                fcntl.flock(fd, how)
                yield
            finally:
                os.close(fd)  # drops the lock

        def save(self, key: Any, data: Any) -> None:
            """numba's ``save`` with the data file written before the index names it (numba: the index first, so
            that a kill between the two left an index naming a data file of an older source)."""
            with self._locked(fcntl.LOCK_EX):
                overloads = self._load_index()  # type: ignore[no-untyped-call]
                name = overloads.get(key)
                if name is None:
                    taken = set(overloads.values())
                    for i in itertools.count(1):
                        name = self._data_name(i)  # type: ignore[no-untyped-call]
                        if name not in taken:
                            break
                self._save_data(name, data)  # type: ignore[no-untyped-call]
                if overloads.get(key) != name:
                    self._save_index({**overloads, key: name})  # type: ignore[no-untyped-call]

        def load(self, key: Any) -> Any:
            with self._locked(fcntl.LOCK_SH):
                return super().load(key)  # type: ignore[no-untyped-call]

    return LockedIndexDataCacheFile


def _stamped_cache(dispatcher: Any) -> Any:
    """A numba ``FunctionCache`` for ``dispatcher`` whose source stamp is :func:`source_stamp`."""
    return _cache_class(_package_root(dispatcher.py_func))(dispatcher.py_func)


class _CacheOnUse:
    """A kernel's on-disk cache (:func:`_stamped_cache`), made when numba first reads it (the kernel's first
    compile): making one finds its folder and tries a file there (~0.4 ms), which a command would otherwise
    pay for every kernel defined, not only those it runs (issue 56).  numba reads a dispatcher's cache only
    through its attributes (``load_overload``, ``save_overload``, ``flush``, ``cache_path``)."""

    def __init__(self, dispatcher: Any) -> None:
        self._dispatcher: Any = dispatcher
        self._made: Any = None

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        if self._made is None:
            try:
                self._made = _stamped_cache(self._dispatcher)
            except (AttributeError, ImportError, TypeError, RuntimeError):  # pragma: no cover - numba changed
                from numba.core.caching import NullCache

                self._made = NullCache()  # no on-disk cache: always correct, only slower to start
        return getattr(self._made, name)


def _compile(fn: Callable[..., Any], options: dict[str, Any]) -> Any:
    from numba import njit

    from .linking import OwnCodeCompiler  # calls between kernels bound inside the caller (runtime/linking.py)

    dispatcher = njit(**{**_SETTINGS, "pipeline_class": OwnCodeCompiler, **options})(fn)
    if hasattr(dispatcher, "enable_caching"):  # not with NUMBA_DISABLE_JIT=1
        dispatcher._cache = _CacheOnUse(dispatcher)
    return dispatcher


@overload
def kernel(fn: F, **options: Any) -> F: ...


@overload
def kernel(fn: None = None, **options: Any) -> Callable[[F], F]: ...


def kernel(fn: Callable[..., Any] | None = None, **options: Any) -> Any:
    """Decorator: ``numba.njit`` with auvplan's settings and a cache that cannot go stale.

    Parameters
    ----------
    fn : callable, optional
        The function to compile (``@kernel``); omitted for ``@kernel(**options)``.
    **options
        Further ``numba.njit`` options (e.g. ``inline="always"``); they override the settings above
        (``fastmath=False``: the IEEE operations of numpy, for a kernel that must match it bit for bit).

    Returns
    -------
    numba dispatcher or decorator
        The compiled kernel (a stand-in called like it until the first kernel runs), or a decorator
        that makes one.  For the type checker the kernel has the signature of ``fn`` (a numba
        dispatcher is called like the function it compiles).

    Raises
    ------
    TypeError
        If ``cache=`` is passed (the cache is managed here).
    """
    if "cache" in options:
        raise TypeError("kernel() manages numba's cache itself; do not pass cache=")
    if fn is None:
        return functools.partial(_deferred, options=options)
    return _deferred(fn, options)


class _Deferred:
    """A kernel whose numba dispatcher is made when the first kernel is used (numba is imported then).

    Importing numba costs ~0.3 s of a command's start, and loading the first cached kernel ~0.25 s more
    (numba's registries): ``validate`` and ``data inspect`` paths that run no kernel need neither
    (issue 56).  At the first call (or attribute read) of any deferred kernel, :func:`_make_all` makes
    the dispatchers of every kernel defined so far and puts each in place of its stand-in wherever a
    module holds it (``from .kernels import k`` included), so that numba, compiling a caller, finds its
    callees as dispatchers (inlined with ``inline="always"`` as before) and Python calls go straight to
    numba; kernels defined afterwards are dispatchers at once.  The compiled code is the same.
    """

    def __init__(self, fn: Callable[..., Any], options: dict[str, Any]) -> None:
        functools.update_wrapper(self, fn)
        self._fn, self._options = fn, options
        self._made: Any = None
        self._aot: Any = None  # {args key: compiled function} of this kernel (aot.table), {} when none

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        if self._made is None:
            compiled = self._aot if self._aot is not None else _aot_of(self)
            if compiled is not _NO_MODULE:
                run = None if kwargs else (compiled.get(aot.args_key(args))
                                           or compiled.get(aot.args_key(args, canonical=True)))
                if run is not None:  # the exact argument types it was built for: numba's own machine code
                    return run(*args)
                aot.MISSES.append(f"{self._fn.__module__}:{self._fn.__qualname__}")
        return _made(self)(*args, **kwargs)

    def __getattr__(self, name: str) -> Any:  # signatures, stats … of the dispatcher
        if name.startswith("__") or name in ("_fn", "_options", "_made", "_aot"):
            raise AttributeError(name)
        if name == "py_func":  # the Python function compiled (the docs' tests read it): no numba for it
            return self._fn
        return getattr(_made(self), name)

    def __reduce__(self) -> tuple[Any, tuple[str, str]]:  # pickled by reference, as a module-level function
        return _by_name, (self._fn.__module__, self._fn.__qualname__)


_PENDING: list[_Deferred] = []
"""Kernels defined, their dispatchers not made yet."""

_MADE = threading.Event()
"""Set once :func:`_make_all` has run: kernels are then made at definition."""

_LOCK = threading.Lock()


def _deferred(fn: Callable[..., Any], options: dict[str, Any]) -> Any:
    if _MADE.is_set():
        return _compile(fn, options)
    stand_in = _Deferred(fn, options)
    with _LOCK:
        if not _MADE.is_set():
            _PENDING.append(stand_in)
            return stand_in
    return _compile(fn, options)


_NO_MODULE: dict[Any, Any] = {}
"""A kernel's ahead-of-time functions when no module is built for its package (else its own dict, empty when the
module lacks the kernel: a call is then a miss)."""


def _aot_of(stand_in: _Deferred) -> dict[Any, Any]:
    """The kernel's ahead-of-time functions (:func:`auvplan.runtime.aot.table`), looked up once."""
    try:
        table = aot.table(_package_root(stand_in._fn))
    except (KeyError, AttributeError):  # a kernel outside a package (``__main__``)
        table = {}
    compiled: dict[Any, Any] = (table.get(f"{stand_in._fn.__module__}:{stand_in._fn.__qualname__}", {}) if table
                                else _NO_MODULE)
    stand_in._aot = compiled
    return compiled


def _made(stand_in: _Deferred) -> Any:
    if stand_in._made is None:
        _make_all()
    return stand_in._made


class _BlasProbe:
    """An import hook that lets numba's registries load without importing ``scipy.linalg`` (issue 56).

    numba's first kernel (also one loaded from the disk cache) loads every registry of numba's, and one of them,
    ``numba.np.arraymath``, asks at its import whether BLAS is there by importing ``scipy.linalg.cython_blas``:
    all of ``scipy.linalg`` (~0.1–0.2 s of CPU, and numpy.f2py through SciPy's array API), which no kernel of
    auvplan's uses.  Just before that module runs (its name looked up on ``sys.meta_path``, once), numba's
    ``ensure_blas`` is replaced for that one call by :func:`_blas_installed`, the same question asked of the
    files, and put back at once; a kernel that does use BLAS (``np.dot``) imports it through numba as before.
    numba's linalg is imported first when it is not yet (a kernel loaded from the disk cache without the
    registries, :mod:`auvplan.runtime.cacheload`, imports arraymath alone for its environment).
    """

    def find_spec(self, name: str, path: Any = None, target: Any = None) -> None:
        if name != "numba.np.arraymath":
            return None
        with contextlib.suppress(ValueError):
            sys.meta_path.remove(self)
        if "scipy.linalg" in sys.modules:
            return None
        import importlib

        # numba's registries import linalg first; a cached kernel's environment may import arraymath alone
        linalg: Any = importlib.import_module("numba.np.linalg")
        real = getattr(linalg, "ensure_blas", None)
        if real is None:
            return None

        def ensure_blas() -> None:  # called once, by arraymath's module-level check
            linalg.ensure_blas = real
            caller = sys._getframe(1).f_globals  # arraymath's (its name read already): numba's own from now on
            if caller.get("ensure_blas") is ensure_blas:
                caller["ensure_blas"] = real
            if not _blas_installed():
                raise ImportError("scipy 0.16+ is required for linear algebra")  # numba's own words

        linalg.ensure_blas = ensure_blas
        return None  # found by the next finder, as always


def _blas_installed() -> bool:
    """Whether SciPy's ``linalg.cython_blas`` extension is installed (found, not imported)."""
    import importlib.machinery
    import importlib.util

    scipy: Any = sys.modules.get("scipy")
    try:
        spec: Any = None if scipy is not None else importlib.util.find_spec("scipy")
        places = list(scipy.__path__ if scipy is not None else spec.submodule_search_locations)
    except (AttributeError, ImportError, TypeError, ValueError):
        return False
    return any((Path(p) / "linalg" / f"cython_blas{suffix}").is_file()
               for p in places for suffix in importlib.machinery.EXTENSION_SUFFIXES)


def _probe_blas() -> None:
    """Put a :class:`_BlasProbe` first on ``sys.meta_path`` (ahead of the finder that would find numba's
    ``arraymath``), unless that module is loaded already or a probe is there."""
    if "numba.np.arraymath" not in sys.modules and not any(type(f) is _BlasProbe for f in sys.meta_path):
        sys.meta_path.insert(0, _BlasProbe())


def _make_all() -> None:
    """Make every pending kernel's dispatcher and put it in place of its stand-in in every module."""
    with _LOCK:
        if _MADE.is_set():
            return
        _probe_blas()
        for k in _PENDING:
            k._made = _compile(k._fn, k._options)
        for module in list(sys.modules.values()):
            names = getattr(module, "__dict__", None) if isinstance(module, types.ModuleType) else None
            for name, value in list((names or {}).items()):
                if type(value) is _Deferred:
                    names[name] = value._made  # type: ignore[index]
        _PENDING.clear()
        _MADE.set()


def _by_name(module: str, qualname: str) -> Any:
    import importlib

    obj: Any = importlib.import_module(module)
    for part in qualname.split("."):
        obj = getattr(obj, part)
    return obj
