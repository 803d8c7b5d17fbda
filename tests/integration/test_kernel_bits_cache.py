"""A kernel computes the same bits whether this process compiled it, loaded it from numba's disk cache,
loaded its callee first, or compiled it against its callee loaded from the cache (``auvplan.runtime.linking``).

The kernel is the seabed's ``cell_extremes``, which calls ``_segment`` (another kernel, not inlined by LLVM).
Before the fix, a process that compiled it called ``_segment``'s own machine code and a process that loaded
it from the cache called the copy compiled into ``cell_extremes``: the two fuse a different product of
``(1 - v) z[i, k] + v z[i, k + 1]`` into a multiply-add (``fastmath`` contract), and the extremes differed in
their last bits (and a cached process that ran ``_segment`` first computed the fresh process's bits).
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import llvmlite.binding as ll
import pytest

from auvplan.runtime.linking import bind_locally

CODE = textwrap.dedent("""
    import sys
    import numpy as np
    import auvplan.world.seabed as sb

    rng = np.random.default_rng(7)
    z = rng.normal(size=(23, 31)) * 50.0  # data 23 x 31, a model grid 13 x 17 turned 17 degrees across it
    a = np.deg2rad(17.0)
    jj, ii = np.mgrid[0:13, 0:17] * 1.37
    fr = 5.4 + np.cos(a) * jj - 0.8 * np.sin(a) * ii
    fc = 2.3 + np.sin(a) * jj + 1.1 * np.cos(a) * ii
    if sys.argv[1] == "callee-first":  # _segment's own code loaded before its caller's
        e = np.zeros(2)
        sb._segment(z, e, e, e, np.zeros(4), 0.0, 0.0, 1.0, 0.0, np.zeros(3), np.zeros(16))
    ext = sb.cell_extremes(z, fr, fc, sb.data_at(z, fr, fc))
    assert ext.shape == (12, 16, 3) and np.isfinite(ext).all()
    compiled = sum(sb.cell_extremes.stats.cache_misses.values())
    print(compiled, ext.tobytes().hex())
""")


def _run(env: dict[str, str], how: str) -> tuple[int, str]:
    """``cell_extremes`` on a fixed grid in a new process: (its compiles in that process, its bytes in hex)."""
    r = subprocess.run([sys.executable, "-c", CODE, how], env=env, capture_output=True, text=True, check=True)
    compiled, bits = r.stdout.split()
    return int(compiled), bits


@pytest.mark.skipif(os.environ.get("NUMBA_DISABLE_JIT") == "1", reason="no compilation with NUMBA_DISABLE_JIT=1")
def test_kernel_bits_equal_compiled_and_cached(tmp_path: Path) -> None:
    env = {k: v for k, v in os.environ.items() if k != "AUVPLAN_NUMBA_REFRESH"}
    env["NUMBA_CACHE_DIR"] = str(tmp_path / "numba")  # empty: the first process compiles every kernel
    compiled, fresh = _run(env, "plain")
    assert compiled == 1
    assert list((tmp_path / "numba").rglob("seabed.cell_extremes-*.nbi")), "nothing was written to the cache"
    for how, extra in (("plain", {}), ("callee-first", {}), ("plain", {"AUVPLAN_NUMBA_REFRESH": "1"})):
        compiled, bits = _run({**env, **extra}, how)
        assert compiled == 0, f"{how} {extra}: compiled, not loaded from the cache"
        assert bits == fresh, f"{how} {extra}: the cached kernel's bits differ from the compiled one's"
    for f in (tmp_path / "numba").rglob("seabed.cell_extremes-*"):  # the callee cached, its caller not
        f.unlink()
    compiled, bits = _run(env, "plain")
    assert compiled == 1 and bits == fresh, "compiled against the cached callee: other bits"


IR = """
define linkonce_odr double @callee(double %x) {
  %y = fmul double %x, 3.0
  ret double %y
}
define weak_odr double @other(double %x) {
  ret double %x
}
declare double @outside(double)
define double @caller(double %x) {
  %a = call double @callee(double %x)
  %b = call double @outside(double %a)
  ret double %b
}
"""


def test_bind_locally_internalises_only_shared_definitions() -> None:
    module = ll.parse_assembly(IR)
    assert bind_locally(module) == 2
    linkage = {fn.name: fn.linkage for fn in module.functions}
    assert linkage == {"callee": ll.Linkage.internal, "other": ll.Linkage.internal,
                       "outside": ll.Linkage.external, "caller": ll.Linkage.external}
    module.verify()
    assert bind_locally(module) == 0
