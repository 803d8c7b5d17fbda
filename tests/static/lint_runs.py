"""The static checkers' runs the suite starts early.

mypy's run over src/ costs ~40 s of CPU on a fresh checkout (no ``.mypy_cache``: CI).  When
``tests/static/test_lint.py::test_mypy_clean`` is among the collected tests, ``tests/conftest.py`` starts that
very command as soon as collection ends, in a process of its own (on CI's second core, which the one pytest
process leaves idle); the test then waits for it and asserts on its exit status and output as before.  Run on its
own, the test starts it itself.  Whatever is still running when the session ends is stopped.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import IO

ROOT = Path(__file__).resolve().parents[2]

_RUNS: dict[tuple[str, ...], tuple[subprocess.Popen, IO[bytes]]] = {}


def tool(name: str) -> str:
    """The console script ``name`` of this interpreter's environment (else the one on PATH); a path as it is."""
    if Path(name).is_absolute():
        return name
    exe = Path(sys.executable).with_name(name)
    return str(exe) if exe.exists() else (shutil.which(name) or name)


def start(*command: str, nice: bool = True) -> None:
    """Start ``command`` (a console script and its arguments) in the repository's root, once; ``nice``: at nice
    10 where ``nice`` exists, so that it fills the core the suite leaves idle and never slows the suite's own
    process (the kernels' warm-up, tests/warm_kernels.py, runs at the suite's priority: it works for the suite)."""
    if command not in _RUNS:
        out = tempfile.TemporaryFile()
        nice_cmd = ["nice", "-n", "10"] if nice and shutil.which("nice") else []
        proc = subprocess.Popen([*nice_cmd, tool(command[0]), *command[1:]], cwd=ROOT, stdout=out,
                                stderr=subprocess.STDOUT)
        _RUNS[command] = (proc, out)


def verdict(*command: str) -> tuple[int, str]:
    """``command``'s exit status and output (stdout and stderr), started now if it was not started earlier."""
    start(*command)
    proc, out = _RUNS.pop(command)
    code = proc.wait()
    out.seek(0)
    text = out.read().decode(errors="replace")
    out.close()
    return code, text


def stop_all() -> None:
    """Stop the runs no test has waited for (a session cut short, ``--collect-only``)."""
    for proc, out in _RUNS.values():
        proc.kill()
        proc.wait()
        out.close()
    _RUNS.clear()
