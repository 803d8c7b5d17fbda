"""Where the CPU of one ``auvplan`` command goes: imports, building the scenario, planning (issue 33).

Runs the real command line in child processes and measures CPU time (user + sys), not wall time, so
the figures hold on a loaded machine::

    python tools/startup_split.py plan marcus-wake --json    # the split of a plan
    python tools/startup_split.py --version                   # the start-up alone

1. the command itself (``python -m auvplan ARGS``): its CPU and peak memory, and the modules it
   imported (recorded at exit);
2. a child that imports exactly those modules, in the same order: the CPU of the imports;
3. for ``plan SCENARIO``: a child that imports them, then loads and builds the scenario
   (``auvplan.load_scenario``) and plans it (``auvplan.plan``, the seed given by ``--seed``, 1 by
   default), each timed with ``time.process_time``.

The rest (the interpreter's start, parsing the arguments, writing the output) is the difference.
Run it twice and read the second (numba's cache and the OS's file cache warm).  Set ``PYTHONPATH`` to
measure another checkout.
"""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import tempfile
from pathlib import Path

__all__ = ["child_cpu", "main"]

_RUN = """
import atexit, runpy, sys
def _dump():
    with open({out!r}, "w") as f:
        f.write("\\n".join(m for m in list(sys.modules) if m != "__main__"))
atexit.register(_dump)
sys.argv = ["auvplan", *{args!r}]
runpy.run_module("auvplan", run_name="__main__", alter_sys=True)
"""

_IMPORTS = """
import importlib, sys
for name in open({mods!r}).read().split():
    if name not in sys.modules:
        try:
            importlib.import_module(name)
        except Exception:
            pass
"""

_SPLIT = _IMPORTS + """
import json, time
import auvplan
t0 = time.process_time()
world, mission = auvplan.load_scenario({scenario!r})
t1 = time.process_time()
result = auvplan.plan(auvplan.planning_problem(world, mission), mission.planner, rng={seed})
t2 = time.process_time()
print(json.dumps({{"build": t1 - t0, "plan": t2 - t1, "status": str(result.status)}}))
"""


def child_cpu(code: str) -> tuple[float, float, str]:
    """CPU seconds (user + sys), peak memory (MB) and standard output of ``python -c code``."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, after.ru_maxrss / 1024.0, run.stdout


def main(argv: list[str] | None = None) -> int:
    """Command line: the ``auvplan`` arguments to measure."""
    args = list(sys.argv[1:] if argv is None else argv)
    if not args:
        print(__doc__)
        return 2
    with tempfile.TemporaryDirectory() as tmp:
        mods = str(Path(tmp) / "modules.txt")
        total, rss, _ = child_cpu(_RUN.format(out=mods, args=args))
        n_mods = len(Path(mods).read_text().split())
        imports, _, _ = child_cpu(_IMPORTS.format(mods=mods))
        split = None
        if len(args) >= 2 and args[0] == "plan":
            seed = args[args.index("--seed") + 1] if "--seed" in args else "1"
            _, _, out = child_cpu(_SPLIT.format(mods=mods, scenario=args[1], seed=int(seed)))
            split = json.loads(out.strip().splitlines()[-1])
    print(f"auvplan {' '.join(args)}  (load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs)")
    print(f"  the command          {total:5.2f} s CPU   peak memory {rss:4.0f} MB   {n_mods} modules imported")
    print(f"  its imports          {imports:5.2f} s CPU   ({100 * imports / total:3.0f} %)")
    if split is not None:
        b, p = split["build"], split["plan"]
        print(f"  scenario build       {b:5.2f} s CPU   ({100 * b / total:3.0f} %)")
        print(f"  plan                 {p:5.2f} s CPU   ({100 * p / total:3.0f} %)  {split['status']}")
        rest = total - imports - b - p
        print(f"  the rest             {rest:5.2f} s CPU   ({100 * rest / total:3.0f} %)  (start, arguments, output)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
