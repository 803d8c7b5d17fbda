"""Round 10's survivors of the ahead-of-time kernels' binding (``runtime/aot.py``'s argument keys, ``runtime/jit.py``'s
``_Deferred.__call__``; docs/mutants.md section 10), checked in this process.

``tests/integration/test_aot.py`` binds built kernels in fresh processes (a mutant planted in this process never
reaches them), and its in-process key test accepts a key of ``None`` (never bound: numba, correct but slow) for any
value: a key that stopped matching for Python ints, numpy scalars, tuples, the canonical look-up or a 2-D array inside
a tuple passed it, and so did a tuple holding a value of no known type keyed as if that element were absent (a false
match), and the binding itself (used, skipped, or looked up the second way).

Oracles: ``numba.typeof`` through the build's own ``type_key`` (a value numba types as a type the build expresses has
exactly that key, both look-ups); the design's refusals (a value numba would type otherwise, or not at all, has no
key); a stub compiled function and a plain-Python stand-in for numba, which record which one ran.
"""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from test_aot import VALUES, ro, unaligned  # noqa: F401 - the literals of VALUES name ro and unaligned

from auvplan.runtime import aot, jit

EXTRA = ["10**6", "2**62", "-(2**63)", "(np.zeros((3, 4)), 1.0)", "(1, np.zeros((3, 4), order='F'))",
         "((np.int32(2), np.zeros((2, 2))[:, ::2]), True)", "np.zeros((2, 3), np.uint8)"]
REFUSED = ["2**63", "-(2**63) - 1", "np.matrix(np.zeros((3, 4)))", "'x'", "None", "object()", "[1.0]",
           "(np.zeros(3), 'x')", "(1.0, 2**63)", "((1.0, None), 2.0)"]


def _built_key(numba, value):
    from auvplan.runtime.aotbuild import type_key

    try:
        t = numba.typeof(value)
    except (ValueError, numba.core.errors.NumbaError):
        return None
    k = type_key(t)
    return None if k is None else aot.runtime_key([k])


def test_a_value_of_a_built_type_has_exactly_its_key_both_ways():
    numba = pytest.importorskip("numba")
    checked = 0
    for text in VALUES + EXTRA:
        if text in ("2**63",):  # numba's uint64: refused on purpose (below)
            continue
        v = eval(text)  # noqa: S307 - the literals above
        want = _built_key(numba, v)
        if want is None:  # numba types it as nothing the build expresses (a big-endian or unaligned array)
            continue
        assert aot.args_key((v,)) == want, text
        assert aot.args_key((v,), canonical=True) == want, text
        assert aot.arg_key(v) == want and aot.arg_key(v, canonical=True) == want, text
        checked += 1
    assert checked >= 36
    x = np.arange(5.0)
    copy = pickle.loads(pickle.dumps(x))
    want = _built_key(numba, x)
    assert aot.args_key((copy,)) != want  # an equal dtype, not numpy's own object: the case under test
    assert aot.args_key((copy,), canonical=True) == want
    assert aot.args_key(((copy, 1.0),), canonical=True) == _built_key(numba, (x, 1.0))


@pytest.mark.filterwarnings("ignore::PendingDeprecationWarning")  # np.matrix, refused
def test_a_value_numba_types_otherwise_or_not_at_all_has_no_key():
    for text in REFUSED:
        v = eval(text)  # noqa: S307 - the literals above
        assert aot.arg_key(v) is None and aot.args_key((v,)) is None and aot.args_key((1.0, v)) is None, text
        assert aot.args_key((v,), canonical=True) is None, text


def test_the_first_use_fills_the_type_tables(monkeypatch):
    """A fresh process: the scalar and array tables are empty until the first key is asked for."""
    args = (1, np.float32(2.0), np.zeros((2, 3)), (True, 1j), 1.5)
    want = aot.args_key(args)
    assert want is not None
    for first in (lambda: aot.args_key(args), lambda: aot.arg_key(args[0])):
        monkeypatch.setattr(aot, "_SCALARS", {})
        monkeypatch.setattr(aot, "_ARRAY", [])
        first()
        assert aot._ARRAY == [np.ndarray] and aot._SCALARS[int] == "int64" and aot._SCALARS[np.bool_] == "bool"
        assert aot.args_key(args) == want


def _py(x, y=0.0):
    return ("python", x, y)


def test_a_call_runs_the_built_function_only_for_exactly_its_types(monkeypatch):
    """The stand-in of a kernel with a built table: an exact key runs the built function, found the fast way or the
    canonical way; any other call (another type, keywords) is a miss and runs the kernel (here its Python function
    standing in for numba); without a built module nothing is a miss."""
    monkeypatch.setattr(jit, "_made", lambda stand_in: stand_in._fn)  # numba's dispatcher: the Python function
    monkeypatch.setattr(aot, "MISSES", [])
    x = np.arange(4.0)
    ran = []

    def built(*args):
        ran.append(args)
        return ("built", *args)

    d = jit._Deferred(_py, {})
    d._aot = {aot.args_key((1.5, 2.0)): built, aot.runtime_key([["<f8", 1, "C", True, True], "float64"]): built}
    assert d(1.5, 2.0) == ("built", 1.5, 2.0) and aot.MISSES == []
    assert d(x, 3.0)[0] == "built" and aot.MISSES == []
    copy = pickle.loads(pickle.dumps(x))
    assert d(copy, 3.0)[0] == "built" and aot.MISSES == []  # the second look-up
    assert d(1.5, y=2.0) == ("python", 1.5, 2.0)  # keywords: numba
    assert d(1, 2.0) == ("python", 1, 2.0)  # an int: not the float64 built
    assert d(x[::2], 3.0)[0] == "python"  # strided: not the C array built
    assert aot.MISSES == ["test_mutants24_aot:_py"] * 3
    assert len(ran) == 3
    d._aot = jit._NO_MODULE  # no module built for the package: numba, not a miss
    assert d(1.5, 2.0) == ("python", 1.5, 2.0) and aot.MISSES == ["test_mutants24_aot:_py"] * 3
