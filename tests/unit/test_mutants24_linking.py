"""Round 10's survivors of ``runtime/linking.py`` (docs/mutants.md section 10): ``OwnCodeCompiler`` really compiles
into an ``OwnCodeLibrary`` whose final module keeps no shared copy of a callee, checked in this process.

``tests/integration/test_kernel_bits_cache.py`` checks the bits in fresh processes (a planted mutant in this process
never reaches them), and ``bind_locally`` on a hand-written module; a compiler that kept numba's own library (the
test of ``state.library`` or of the codegen's library class inverted) passed both in a mutation run.

Oracle: the linkage of every function the caller's optimised module defines (llvmlite), against the same caller
compiled by numba's default compiler, whose module holds the callee's ``linkonce_odr`` copy (the case under test).
"""

from __future__ import annotations

import os

import pytest

pytestmark = pytest.mark.skipif(os.environ.get("NUMBA_DISABLE_JIT") == "1", reason="nothing is compiled")


def _final_linkages(dispatcher):
    library = dispatcher.overloads[dispatcher.signatures[0]].library
    return library, {fn.name: fn.linkage for fn in library._final_module.functions if not fn.is_declaration}


def test_a_kernel_compiled_by_own_code_compiler_keeps_no_shared_callee():
    import numba

    from auvplan.runtime.linking import _SHARED, OwnCodeCompiler, OwnCodeLibrary

    @numba.njit(cache=False)
    def callee(n):  # recursive: LLVM cannot inline it away, the caller's module keeps a copy of it
        if n <= 1:
            return 1.0
        return n * callee(n - 1)

    def caller(x):
        return callee(x) * 2.0 + callee(x + 1)

    plain = numba.njit(cache=False)(caller)
    own = numba.njit(cache=False, pipeline_class=OwnCodeCompiler)(caller)
    assert own(6) == plain(6) == 2.0 * 720.0 + 5040.0
    library, linkage = _final_linkages(plain)
    assert not isinstance(library, OwnCodeLibrary)
    assert any(v in _SHARED for v in linkage.values()), linkage  # numba's own: the callee's weak copy
    library, linkage = _final_linkages(own)
    assert isinstance(library, OwnCodeLibrary)
    assert not any(v in _SHARED for v in linkage.values()), linkage
    assert len(linkage) >= 2  # the callee's copy is still there, bound inside the caller's own object
