"""Kill ``auvplan run --out`` at every atomic replace (before and after it), re-run, check the folder.

The exhaustive version of
``tests/integration/test_crash_safe.py::test_a_run_killed_while_writing_is_completed_by_a_re_run``
(two runs per point, about 50 points: minutes, so not in the default suite)::

    .venv/bin/python tools/kill_points.py [SCENARIO]
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from pathlib import Path

KILL_AT = """
import os, signal
_real, _n, _out = os.replace, [0], {out!r}
def _replace(a, b, **kw):
    if os.path.dirname(os.fspath(b)) != _out:  # numba's cache files (a cold cache): not a point of the count
        return _real(a, b, **kw)
    _n[0] += 1
    if _n[0] == {k} and {before}:
        os.kill(os.getpid(), signal.SIGKILL)
    _real(a, b, **kw)
    if _n[0] == {k}:
        os.kill(os.getpid(), signal.SIGKILL)
os.replace = _replace
"""


def _auvplan(args: list[str], pre: str = "") -> int:
    code = f"import sys\n{pre}\nfrom auvplan import cli\nsys.exit(cli.main(sys.argv[1:]))"
    return subprocess.run([sys.executable, "-c", code, "-q", *args], capture_output=True, timeout=600).returncode


def main() -> int:
    scenario = sys.argv[1] if len(sys.argv) > 1 else "track-single"
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        k = 0
        while True:
            k += 1
            for before in (True, False):
                out = Path(tmp) / f"k{k}{before}"
                code = _auvplan(["run", scenario, "--out", str(out)], KILL_AT.format(k=k, before=before, out=str(out)))
                if code != -9:
                    print(f"{k - 1} replaces in a run; {failures} failures")
                    return 1 if failures else 0
                again = _auvplan(["run", scenario, "--out", str(out)])
                names = {p.name for p in out.iterdir()}
                mine = set(json.loads((out / ".auvplan-manifest.json").read_text())["files"])
                ok = again == 0 and not any(n.endswith(".tmp") for n in names) and \
                    names - {".auvplan-manifest.json", ".auvplan.lock"} <= mine
                failures += not ok
                print(f"kill {'before' if before else 'after'} replace {k}: re-run exit {again}, "
                      f"{'whole' if ok else 'BROKEN'}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
