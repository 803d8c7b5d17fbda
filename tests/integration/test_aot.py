"""Kernels compiled ahead of time (``auvplan kernels build``, issue 56): bound only on an exact type match, never
stale, the JIT's bits, and a build that cannot be done leaves numba as before.

One small package of kernels is built once (a C compile: ~4 s of CPU); each check runs in a fresh process, where
numba is not imported until a kernel falls back to it.
"""

from __future__ import annotations

import json
import os
import pickle
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from auvplan.runtime import aot

pytestmark = pytest.mark.skipif(os.environ.get("NUMBA_DISABLE_JIT", "0") not in ("", "0"),
                                reason="nothing is compiled with NUMBA_DISABLE_JIT=1")

KERNELS = """
import numpy as np

from auvplan.runtime.jit import kernel


@kernel
def axpy(a, x, y):
    out = np.empty_like(x)
    for i in range(x.shape[0]):
        out[i] = a * x[i] + y[i]  # fused into one multiply-add where the CPU has one (fastmath "contract")
    return out


@kernel
def ratio(x, y):
    return x / y  # error_model "numpy": inf, not ZeroDivisionError


@kernel(fastmath=False)
def horner(c, t):
    out = np.empty_like(t)
    for i in range(t.shape[0]):
        acc = 0.0
        for j in range(c.shape[0]):
            acc = acc * t[i] + c[j]  # IEEE: no fusion
        out[i] = acc
    return out


@kernel
def weighted(pair, w):
    a, s = pair
    return (a * w).sum() * s + {bias}


@kernel
def never_before(x):
    return 2.0 * x
"""

CALLS = """
import numpy as np
import apkg.k as k
rng = np.random.default_rng(7)
x, y = rng.normal(size=257), rng.normal(size=257)
c, t = rng.normal(size=9), rng.uniform(-3, 3, size=101)
w = rng.normal(size=(5, 3))
calls = [("axpy", (1.0 / 3.0, x, y)), ("ratio", (1.0, 0.0)), ("ratio", (3.0, 7.0)),
         ("horner", (c, t)), ("weighted", ((w, 0.1), w))]
"""


def _env(**extra: str) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("AUVPLAN_AOT", "AUVPLAN_AOT_DIR", "NUMBA_CACHE_DIR")}
    return {**env, **extra}


def _py(code: str, cwd: Path, **env: str) -> subprocess.CompletedProcess[str]:
    path = os.pathsep.join([str(cwd), *sys.path])
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], cwd=cwd, capture_output=True, text=True,
                          env=_env(PYTHONPATH=path, **env))


def _package(root: Path, bias: str = "0.0") -> Path:
    (root / "apkg").mkdir(parents=True)
    (root / "apkg" / "__init__.py").write_text("")
    (root / "apkg" / "k.py").write_text(KERNELS.format(bias=bias))
    return root


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """(package root, module folder): the kernels run once through numba (its cache), then built ahead of time."""
    root = _package(tmp_path_factory.mktemp("aot"))
    where = root / "built"
    r = _py(CALLS + textwrap.dedent(f"""
        import json
        from pathlib import Path
        from auvplan.runtime import aotbuild
        for name, args in calls:
            getattr(k, name)(*args)
        try:
            b = aotbuild.build("apkg", where=Path({str(where)!r}))
        except aotbuild.BuildError as exc:
            print(json.dumps({{"error": str(exc)}}))
        else:
            print(json.dumps({{"signatures": b.signatures, "kernels": b.kernels}}))
        """), root, AUVPLAN_AOT="0")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout.strip().splitlines()[-1])
    if "error" in out and (out["error"].startswith(("CompileError", "LinkError", "DistutilsExecError"))
                           or "compiler" in out["error"]):
        pytest.skip(f"no C toolchain here (a compiler, Python's headers): {out['error']}")
    assert out == {"signatures": 4, "kernels": 4}, out
    return root, where


RUN = CALLS + """
import pickle, sys
from auvplan.runtime import aot
first = [getattr(k, name)(*args) for name, args in calls]
before = ("numba" in sys.modules, list(aot.MISSES))
{after}
jit = [getattr(k, name)(*args) for name, args in calls]  # the dispatchers, made at the first miss
sys.stdout.buffer.write(pickle.dumps((first, jit, before, list(aot.MISSES), "numba" in sys.modules)))
"""


def _run(root: Path, where: Path, after: str, **env: str) -> tuple:
    r = subprocess.run([sys.executable, "-c", RUN.replace("{after}", after)], cwd=root, capture_output=True,
                       env=_env(PYTHONPATH=os.pathsep.join([str(root), *sys.path]), AUVPLAN_AOT_DIR=str(where),
                                **env))
    assert r.returncode == 0, r.stderr.decode()
    return pickle.loads(r.stdout)


def _same_bits(a, b) -> bool:
    return np.asarray(a).tobytes() == np.asarray(b).tobytes() and np.asarray(a).dtype == np.asarray(b).dtype


def test_built_kernels_give_the_jits_bits_without_numba(built):
    """Oracle: numba's JIT on the same inputs in the same process (after a call of a type never built makes the
    dispatchers).  ``axpy``'s multiply-adds are fused by the JIT on a CPU with FMA, so a module built for pycc's
    generic CPU (or without the kernel's fastmath flags) differs in the last bits of most elements; ``ratio`` by
    zero is inf under the kernel's ``error_model="numpy"`` (numba's default model raises)."""
    root, where = built
    first, jit, before, misses, numba_after = _run(root, where, "k.axpy(1.0, x.astype(np.float32), y)")
    assert before == (False, [])  # every call bound ahead of time: numba not even imported
    assert misses == ["apkg.k:axpy"] and numba_after
    assert first[1] == np.inf and jit[1] == np.inf
    for name, a, b in zip(["axpy", "ratio", "ratio", "horner", "weighted"], first, jit, strict=True):
        assert _same_bits(a, b), name


OTHER_TYPES = [
    "(1.0, x.astype(np.float32), y.astype(np.float32))",  # dtype
    "(1.0, x[::2], y[::2])",  # layout: strided, numba's 'A'
    "(1, x, y)",  # a Python int, not a float
    "(np.float32(1.0), x, y)",  # a numpy float32
    "(1.0, x.byteswap().view(x.dtype.newbyteorder()), y)",  # the same values, big-endian
    "(1.0, ro, y)",  # read-only
    "(1.0, np.matrix(x), y)",  # an ndarray subclass
]


def test_a_call_of_any_other_type_goes_to_numba(built):
    """Exact match or numba: a call is bound only to a built signature of exactly its types (a float32 array run
    as float64 would read garbage); any other — a type never built, keywords — falls back to numba, unconverted, and
    gives numba's own answer."""
    root, where = built
    code = f"""
        import pickle
        import sys
        import numpy as np
        import apkg.k as k
        from auvplan.runtime import aot
        rng = np.random.default_rng(7)
        x, y = rng.normal(size=257), rng.normal(size=257)
        ro = x.copy()
        ro.setflags(write=False)
        built = aot.table({str(root / "apkg")!r})["apkg.k:axpy"]
        assert aot.args_key((1.0, x, y)) in built
        copy = pickle.loads(pickle.dumps(x))  # an equal dtype, not numpy's own object: found the second way
        assert aot.args_key((1.0, copy, y), canonical=True) in built
        for args in [{", ".join(OTHER_TYPES)}]:
            key = aot.args_key(args)
            assert key not in built and aot.args_key(args, canonical=True) not in built, key
        got = k.axpy(a=1.0 / 3.0, x=x, y=y)
        assert aot.MISSES == ["apkg.k:axpy"] and "numba" in sys.modules
        assert got.tobytes() == k.axpy(1.0 / 3.0, x, y).tobytes()  # numba's dispatcher now, also positionally
        print("fell back")
        """
    r = _py(code, root, AUVPLAN_AOT_DIR=str(where))
    assert r.returncode == 0 and "fell back" in r.stdout, r.stderr


def test_a_kernel_the_module_lacks_goes_to_numba(built):
    """A kernel never compiled before the build is not in the module: its call is a miss, numba runs it."""
    root, where = built
    code = """
        import sys
        import apkg.k as k
        from auvplan.runtime import aot
        print(k.never_before(1.5), aot.MISSES, "numba" in sys.modules)
        """
    r = _py(code, root, AUVPLAN_AOT_DIR=str(where))
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["3.0", "['apkg.k:never_before']", "True"]


VALUES = [
    "np.zeros(4)", "np.zeros(4, np.float32)", "np.zeros(4, np.int64)", "np.zeros(4, np.int32)",
    "np.zeros(4, np.uint32)", "np.zeros(4, bool)", "np.zeros(4, np.int8)", "np.zeros(4, np.complex128)",
    "np.zeros((3, 4))", "np.zeros((3, 4), order='F')", "np.zeros((3, 4))[:, ::2]", "np.zeros((3, 4))[::2]",
    "np.zeros((3, 4, 2))", "np.zeros((3, 1))", "np.zeros((1, 3), order='F')", "np.zeros(())", "np.zeros(4)[::2]",
    "ro(np.zeros(4))", "ro(np.zeros((3, 4), order='F'))", "unaligned()", "np.zeros(4, '>f8')",
    "1.0", "1", "True", "1j", "np.float64(1)", "np.float32(1)", "np.int64(1)", "np.int32(1)", "np.bool_(1)",
    "np.uint32(1)", "(1.0, 2.0)", "(np.zeros(3), 1.0)", "(np.zeros(3), (1, ro(np.zeros(2))))", "2**63", "-(2**63)",
]


def ro(a):
    a.setflags(write=False)
    return a


def unaligned():
    return np.frombuffer(bytes(8 * 5), dtype=np.float64, count=4, offset=1)


def test_argument_keys_are_equal_exactly_when_numbas_types_are():
    """Oracle: ``numba.typeof``.  For every pair of values, the key of a call (``args_key``) equals the key built
    from the other's numba type (``runtime_key(type_key(…))``) if and only if numba types them alike; a value whose
    type the build cannot express has no such key and is never bound."""
    numba = pytest.importorskip("numba")
    from auvplan.runtime.aotbuild import type_key

    values = [eval(v) for v in VALUES]  # noqa: S307 - the literals above
    typed = []
    for v in values:
        try:
            typed.append(numba.typeof(v))
        except (ValueError, numba.core.errors.NumbaError):  # numba types no such value (a big-endian array)
            typed.append(None)
    built = []
    for text, t in zip(VALUES, typed, strict=True):
        k = None if t is None else type_key(t)
        built.append((text, t, None if k is None else aot.runtime_key([k])))
    assert sum(k is not None for _, _, k in built) >= 30
    for text, v, tv in zip(VALUES, values, typed, strict=True):
        call = aot.args_key((v,))
        for other, t, key in built:
            if key is None:
                continue
            same = call is not None and tv is not None and tv == t
            assert (call == key) == same, (text, other)


def test_an_edited_kernel_never_runs_its_old_build(built, tmp_path):
    """The module's name hashes the kernels' source stamp: the same package with one kernel edited finds no module
    (numba compiles the new source: its value is the oracle), an unedited copy finds the built one."""
    root, where = built
    code = """
        import sys
        import numpy as np
        import apkg.k as k
        from auvplan.runtime import aot
        w = np.ones((2, 2))
        print(k.weighted((w, 1.0), w), "numba" in sys.modules)
        """
    for bias, expected in (("0.0", "4.0 False"), ("1.0", "5.0 True")):
        copy = _package(tmp_path / bias, bias)
        r = _py(code, copy, AUVPLAN_AOT_DIR=str(where))
        assert r.returncode == 0, r.stderr
        assert r.stdout.split() == expected.split(), bias


def test_module_name_follows_the_stamp_and_the_machine(monkeypatch):
    """A new stamp, or another numba setting (a CPU override), is another module name."""
    base = aot.module_name("a" * 64)
    assert base.startswith(aot.PREFIX) and base.isidentifier()
    assert aot.module_name("b" * 64) != base
    monkeypatch.setenv("NUMBA_CPU_NAME", "generic")
    aot.build_key.cache_clear()
    try:
        assert aot.module_name("a" * 64) != base
    finally:
        aot.build_key.cache_clear()


def test_without_jit_the_kernels_run_as_plain_python(built):
    """``NUMBA_DISABLE_JIT=1``: the built module is not used and the kernel is its Python function (oracle: the
    function's own value; a built, fused ``axpy`` differs from it in the last bits)."""
    root, where = built
    code = """
        import numpy as np
        import sys
        import apkg.k as k
        from auvplan.runtime import aot
        rng = np.random.default_rng(7)
        x, y = rng.normal(size=257), rng.normal(size=257)
        python = k.axpy.py_func
        got = k.axpy(1.0 / 3.0, x, y)
        want = python(1.0 / 3.0, x, y)
        assert aot.table(str(__import__("pathlib").Path(k.__file__).parent)) == {}
        print(got.tobytes() == want.tobytes())
        """
    r = _py(code, root, AUVPLAN_AOT_DIR=str(where), NUMBA_DISABLE_JIT="1")
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "True"


def test_a_build_without_a_compiler_is_one_line_and_changes_nothing(built, tmp_path):
    """No C compiler: :class:`BuildError` with one line, no module written, and the kernels run through numba."""
    root, _ = built
    where = tmp_path / "none"
    code = f"""
        import numpy as np
        import apkg.k as k
        from pathlib import Path
        from auvplan.runtime import aotbuild
        try:
            aotbuild.build("apkg", where=Path({str(where)!r}))
        except aotbuild.BuildError as exc:
            print("BuildError", "\\n" in str(exc))
        print(k.ratio(3.0, 7.0) == 3.0 / 7.0)
        """
    r = _py(code, root, AUVPLAN_AOT_DIR=str(where), CC="/nonexistent/cc", CXX="/nonexistent/c++")
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["BuildError", "False", "True"]
    assert not [p for p in where.iterdir() if not p.name.endswith(".lock")]


def test_the_command_says_so_in_one_line_without_a_compiler(tmp_path):
    """``auvplan kernels build`` without a compiler (or with nothing cached yet): exit 1, one line, no traceback."""
    r = subprocess.run([sys.executable, "-m", "auvplan", "kernels", "build"], capture_output=True, text=True,
                       env=_env(AUVPLAN_AOT_DIR=str(tmp_path), CC="/nonexistent/cc", CXX="/nonexistent/c++"))
    assert r.returncode == 1, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("auvplan: kernels not compiled ahead of time (")
    assert "they run through numba as before" in lines[0] and r.stdout == ""


def test_only_this_pythons_modules_of_other_sources_are_removed(tmp_path):
    """In the package's own folder a build removes the modules (and manifests) of older sources built by this Python;
    another Python's (another extension suffix), the current one and the lock stay."""
    import importlib.machinery

    from auvplan.runtime.aotbuild import _remove_stale

    suffix = importlib.machinery.EXTENSION_SUFFIXES[0]
    current, old = aot.PREFIX + "a" * 20, aot.PREFIX + "b" * 20
    names = [current + suffix, current + ".json", old + suffix, old + ".json", old + ".cpython-399-x.so",
             aot.PREFIX + "build.lock", "unrelated" + suffix]
    for n in names:
        (tmp_path / n).write_text("")
    _remove_stale(tmp_path, current)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(set(names) - {old + suffix, old + ".json"})
