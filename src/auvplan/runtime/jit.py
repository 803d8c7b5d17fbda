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
"""

from __future__ import annotations

import functools
import hashlib
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar, overload

from numba import njit

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
    for path in sorted(Path(root).rglob("*.py")):
        data = path.read_bytes()
        if b"@kernel" in data:
            h.update(str(path.relative_to(root)).encode() + b"\0" + data + b"\0")
    return h.hexdigest()


def _package_root(py_func: Callable[..., Any]) -> str:
    top = sys.modules[py_func.__module__.split(".")[0]]
    file = getattr(top, "__file__", None) or sys.modules[py_func.__module__].__file__ or "."
    return str(Path(file).resolve().parent)


def _stamped_cache(dispatcher: Any) -> Any:
    """A numba ``FunctionCache`` for ``dispatcher`` whose source stamp is :func:`source_stamp`."""
    from numba.core import caching

    root = _package_root(dispatcher.py_func)

    def stamped(base: Any) -> Any:
        return type("Stamped" + base.__name__, (base,), {"get_source_stamp": lambda self: source_stamp(root)})

    class KernelCacheImpl(caching.CompileResultCacheImpl):
        _locator_classes = [stamped(c) for c in (caching.UserProvidedCacheLocator, caching.InTreeCacheLocator,
                                                  caching.UserWideCacheLocator)]

    class KernelCache(caching.FunctionCache):
        _impl_class = KernelCacheImpl

    return KernelCache(dispatcher.py_func)  # type: ignore[no-untyped-call]  # numba.core.caching is untyped


def _compile(fn: Callable[..., Any], options: dict[str, Any]) -> Any:
    dispatcher = njit(**{**_SETTINGS, **options})(fn)
    if hasattr(dispatcher, "enable_caching"):  # not with NUMBA_DISABLE_JIT=1
        try:
            dispatcher._cache = _stamped_cache(dispatcher)
        except (AttributeError, ImportError, TypeError, RuntimeError):  # pragma: no cover - numba changed
            pass  # no on-disk cache: always correct, only slower to start
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
        The compiled kernel, or a decorator that makes one.  For the type checker the kernel has
        the signature of ``fn`` (a numba dispatcher is called like the function it compiles).

    Raises
    ------
    TypeError
        If ``cache=`` is passed (the cache is managed here).
    """
    if "cache" in options:
        raise TypeError("kernel() manages numba's cache itself; do not pass cache=")
    if fn is None:
        return functools.partial(_compile, options=options)
    return _compile(fn, options)
