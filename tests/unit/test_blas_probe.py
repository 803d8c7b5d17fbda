"""numba's registries loaded without ``scipy.linalg`` (``runtime.jit._BlasProbe``, issue 56), in this process:
the probe put first on ``sys.meta_path`` once, its swap of numba's ``ensure_blas`` for one call and back, the
files' answer to the BLAS question, and a kernel's on-disk cache made at its first read, once.  (The whole hook in
a fresh interpreter: ``tests/integration/test_front_door.py``; a forked mutant cannot reach that one.)"""

from __future__ import annotations

import importlib
import importlib.util
import os
import sys
import types

import pytest

from auvplan.runtime import jit


class _Finder:
    """A finder ahead of which the probe must go."""

    def find_spec(self, name, path=None, target=None):  # noqa: ANN001, ANN201, ARG002
        return None


def test_the_probe_goes_first_on_the_import_path_once_and_only_before_numba_s_arraymath(monkeypatch):
    other = _Finder()
    monkeypatch.setattr(sys, "meta_path", [other])
    monkeypatch.delitem(sys.modules, "numba.np.arraymath", raising=False)
    jit._probe_blas()
    assert type(sys.meta_path[0]) is jit._BlasProbe and sys.meta_path[1:] == [other]
    jit._probe_blas()  # a probe there already: no second one
    assert [type(f) for f in sys.meta_path] == [jit._BlasProbe, _Finder]
    monkeypatch.setattr(sys, "meta_path", [other])
    monkeypatch.setitem(sys.modules, "numba.np.arraymath", types.ModuleType("numba.np.arraymath"))
    jit._probe_blas()  # numba's registries loaded already: nothing to probe
    assert sys.meta_path == [other]


def _armed(monkeypatch, scipy_linalg: bool = False):
    """A probe on a stand-in ``numba.np.linalg`` whose ``ensure_blas`` records its calls."""
    calls: list[str] = []

    def real() -> None:
        calls.append("real")

    linalg = types.SimpleNamespace(ensure_blas=real)
    monkeypatch.setitem(sys.modules, "numba.np.linalg", linalg)
    if scipy_linalg:
        monkeypatch.setitem(sys.modules, "scipy.linalg", types.ModuleType("scipy.linalg"))
    else:
        monkeypatch.delitem(sys.modules, "scipy.linalg", raising=False)
    probe, other = jit._BlasProbe(), _Finder()
    monkeypatch.setattr(sys, "meta_path", [probe, other])
    return probe, other, linalg, real, calls


def test_the_probe_swaps_ensure_blas_for_arraymath_s_one_call_and_puts_numba_s_back(monkeypatch):
    """Any other module: nothing touched.  numba.np.arraymath: the probe leaves the import path, finds nothing
    (the next finder does), and its stand-in, called from arraymath's globals, puts numba's own back in both
    modules and answers from the files (an ImportError in numba's words when SciPy's BLAS is not installed)."""
    probe, other, linalg, real, calls = _armed(monkeypatch)
    assert probe.find_spec("numba.np.arrayobj") is None
    assert sys.meta_path == [probe, other] and linalg.ensure_blas is real
    assert probe.find_spec("numba.np.arraymath") is None
    assert sys.meta_path == [other]
    stand_in = linalg.ensure_blas
    assert stand_in is not real
    monkeypatch.setattr(jit, "_blas_installed", lambda: True)
    arraymath = {"ensure_blas": stand_in}
    exec("ensure_blas()", arraymath)  # noqa: S102 - arraymath's module-level check, in its own globals
    assert linalg.ensure_blas is real and arraymath["ensure_blas"] is real and calls == []

    probe, other, linalg, real, calls = _armed(monkeypatch)
    probe.find_spec("numba.np.arraymath")
    monkeypatch.setattr(jit, "_blas_installed", lambda: False)
    elsewhere = {"check": linalg.ensure_blas, "ensure_blas": "not the stand-in"}
    with pytest.raises(ImportError, match=r"^scipy 0\.16\+ is required for linear algebra$"):
        exec("check()", elsewhere)  # noqa: S102
    assert linalg.ensure_blas is real and elsewhere["ensure_blas"] == "not the stand-in"


def test_the_probe_leaves_numba_alone_when_scipy_linalg_is_loaded_or_numba_s_linalg_has_no_check(monkeypatch):
    probe, other, linalg, real, _ = _armed(monkeypatch, scipy_linalg=True)
    assert probe.find_spec("numba.np.arraymath") is None and sys.meta_path == [other] and linalg.ensure_blas is real
    probe, other, linalg, real, _ = _armed(monkeypatch)
    del linalg.ensure_blas
    assert probe.find_spec("numba.np.arraymath") is None and sys.meta_path == [other]
    assert getattr(linalg, "ensure_blas", None) is None


def test_the_probe_imports_numba_s_linalg_when_arraymath_comes_first(monkeypatch):
    """A kernel loaded from the disk cache without numba's registries (``runtime.cacheload``) rebuilds its
    environments by importing their modules: ``numba.np.arraymath`` may come before ``numba.np.linalg``, whose
    check the probe must still swap (else all of ``scipy.linalg`` is imported, ~0.2 s)."""
    probe, other, linalg, real, calls = _armed(monkeypatch)
    monkeypatch.delitem(sys.modules, "numba.np.linalg")
    imported: list[str] = []

    def import_module(name: str) -> object:
        imported.append(name)
        sys.modules[name] = linalg
        return linalg

    monkeypatch.setattr(importlib, "import_module", import_module)
    assert probe.find_spec("numba.np.arraymath") is None and sys.meta_path == [other]
    assert imported == ["numba.np.linalg"] and linalg.ensure_blas is not real
    monkeypatch.setattr(jit, "_blas_installed", lambda: True)
    arraymath = {"ensure_blas": linalg.ensure_blas}
    exec("ensure_blas()", arraymath)  # noqa: S102
    assert linalg.ensure_blas is real and arraymath["ensure_blas"] is real and calls == []


def test_the_blas_question_asked_of_the_files_before_scipy_is_imported_and_of_a_broken_scipy(monkeypatch):
    """SciPy not imported yet: found from its installed folder (no import), as importing its BLAS says; a
    ``scipy`` in ``sys.modules`` without a ``__path__``: no."""
    installed = importlib.util.find_spec("scipy.linalg.cython_blas") is not None
    monkeypatch.delitem(sys.modules, "scipy", raising=False)
    assert jit._blas_installed() is installed
    assert "scipy" not in sys.modules
    monkeypatch.setitem(sys.modules, "scipy", types.SimpleNamespace())
    assert jit._blas_installed() is False


@pytest.mark.skipif(os.environ.get("NUMBA_DISABLE_JIT") == "1", reason="no dispatcher with NUMBA_DISABLE_JIT=1")
def test_a_kernel_s_cache_is_made_at_its_first_read_and_only_once():
    from numba import njit

    def bump(x):  # noqa: ANN001, ANN202
        return x + 1.0

    dispatcher = njit(bump)
    cache = jit._CacheOnUse(dispatcher)
    assert cache._made is None
    path = cache.cache_path
    made = cache._made
    assert made is not None and cache.cache_path == path and cache._made is made
    assert path == jit._stamped_cache(dispatcher).cache_path
    assert not hasattr(cache, "__wrapped__")  # dunders are not the cache's: inspect and copy see none
