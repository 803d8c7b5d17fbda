"""A kernel loaded from numba's disk cache without numba's registries (``runtime.cacheload``, issue 56): in a
fresh process with a warm cache the kernels are loaded with the refresh deferred (numba's runtime initialised
only) and return what the compiled kernels returned; a cache miss afterwards compiles with the full refresh.
The guard (what may be deferred, the switch, the versions): ``tests/unit/test_cacheload.py``."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

KERNELS = """
import numpy as np

from auvplan.runtime.jit import kernel


@kernel
def grow(x):
    out = np.empty(x.size + 1)  # allocated by numba's runtime (NRT) and handed to Python
    for i in range(x.size):
        out[i] = np.sqrt(x[i]) * np.sin(x[i])
    out[x.size] = -1.0
    return out


@kernel
def bump(v):  # called only after the loads, never cached before: compiled
    return v + 1.5
"""

RUN = """
import json, sys
import numpy as np
import dpkg.k as k
from auvplan.runtime import cacheload
from numba.core.registry import cpu_target

x = np.linspace(0.5, 3.0, 7)
out = {"grow": k.grow(x).tolist()}
out["registries_after_loads"] = cacheload._registries_loaded(cpu_target.target_context)
out["stats"] = dict(cacheload.STATS)
if sys.argv[1] == "miss":  # a signature not in the cache: compiled, numba's full refresh first
    out["bump"] = k.bump(2.0)
    out["registries_after_miss"] = cacheload._registries_loaded(cpu_target.target_context)
print(json.dumps(out))
"""


def _run(root: Path, env: dict, mode: str = "") -> dict:
    r = subprocess.run([sys.executable, "-c", RUN, mode], cwd=root, env=env, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr[-2000:]  # a kernel run before numba's runtime is initialised segfaults
    return json.loads(r.stdout.strip().splitlines()[-1])


@pytest.mark.skipif(os.environ.get("NUMBA_DISABLE_JIT") == "1", reason="no compilation with NUMBA_DISABLE_JIT=1")
def test_a_warm_process_loads_kernels_without_the_registries_and_gets_the_compiled_values(tmp_path):
    from auvplan.runtime import cacheload

    if not cacheload.enabled():
        pytest.skip("numba outside the versions the deferred load was tested with (or AUVPLAN_NUMBA_REFRESH set)")
    pkg = tmp_path / "dpkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "k.py").write_text(textwrap.dedent(KERNELS))
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(tmp_path), *sys.path]))
    env.pop("NUMBA_CACHE_DIR", None)
    env.pop(cacheload.ENV_VAR, None)

    cold = _run(tmp_path, env)  # compiles both kernels (numba's compiler refreshes) and caches them
    assert cold["stats"] == {"deferred": 0, "refreshed": 0} and cold["registries_after_loads"]
    x = np.linspace(0.5, 3.0, 7)
    np.testing.assert_allclose(cold["grow"], [*(np.sqrt(x) * np.sin(x)), -1.0], rtol=1e-13)

    warm = _run(tmp_path, env, "miss")
    assert warm["stats"] == {"deferred": 1, "refreshed": 0} and not warm["registries_after_loads"]
    assert warm["grow"] == cold["grow"]  # the same machine code, bit for bit
    assert warm["bump"] == 3.5
    assert warm["registries_after_miss"]  # the miss compiled with numba's full refresh

