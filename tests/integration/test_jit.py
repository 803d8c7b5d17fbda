"""The kernels' on-disk cache: an edited kernel is recompiled, also inside its callers."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from auvplan.runtime.jit import kernel, source_stamp

CALLEE = """
from auvplan.runtime.jit import kernel


@kernel
def bump(x):
    return x + {step}
"""

CALLER = """
from auvplan.runtime.jit import kernel

from .callee import bump


@kernel
def twice(x):
    return 2.0 * bump(x)


@kernel
def unused(x):
    return x
"""


def _run(root: Path, env: dict) -> float:
    """``twice(1.0)`` in a fresh process; a kernel never called has no on-disk cache object made (issue 56)."""
    code = ("import kpkg.caller as c; v = c.twice(1.0)\n"
            "assert c.unused._cache._made is None and c.twice._cache._made is not None\nprint(v)")
    r = subprocess.run([sys.executable, "-c", code], cwd=root, env=env, capture_output=True, text=True, check=True)
    return float(r.stdout.strip())


@pytest.mark.skipif(os.environ.get("NUMBA_DISABLE_JIT") == "1", reason="no compilation with NUMBA_DISABLE_JIT=1")
def test_edited_callee_kernel_is_recompiled_in_its_caller(tmp_path):
    """A caller kernel compiles its callee (from another module) into itself.  Numba's own cache
    stamps the caller with the caller's file only and would load the old machine code after an
    edit of the callee; auvplan's stamp covers every kernel module of the package."""
    pkg = tmp_path / "kpkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "caller.py").write_text(textwrap.dedent(CALLER))
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(tmp_path), *sys.path]))
    env.pop("NUMBA_CACHE_DIR", None)
    (pkg / "callee.py").write_text(textwrap.dedent(CALLEE.format(step="1.0")))
    assert _run(tmp_path, env) == 4.0
    assert any((pkg / "__pycache__").glob("caller.twice-*.nbi")), "the caller was not cached on disk"
    assert _run(tmp_path, env) == 4.0  # served from the cache
    (pkg / "callee.py").write_text(textwrap.dedent(CALLEE.format(step="2.0")))  # only the callee changes
    assert _run(tmp_path, env) == 6.0


def test_source_stamp_follows_kernel_sources_only(tmp_path):
    (tmp_path / "a.py").write_text("@kernel\ndef f(x):\n    return x\n")
    (tmp_path / "b.py").write_text("def g(x):\n    return x\n")
    first = source_stamp.__wrapped__(str(tmp_path))
    (tmp_path / "b.py").write_text("def g(x):\n    return -x\n")
    assert source_stamp.__wrapped__(str(tmp_path)) == first  # no kernel there
    (tmp_path / "a.py").write_text("@kernel\ndef f(x):\n    return -x\n")
    assert source_stamp.__wrapped__(str(tmp_path)) != first


def test_kernel_refuses_its_own_cache_option():
    with pytest.raises(TypeError, match="cache"):
        kernel(lambda x: x, cache=False)
