"""The front door against the previous release: CPU of the commands people type, A/B interleaved.

    nice -n 5 .venv/bin/python benchmarks/front_door.py --prev f5c6a15 --rounds 3
    make bench-front                      # the same, every built-in, writes docs/figures/bench-front.md

Issue #56 (and #59's "plan CPU per built-in ≤ the previous release's"): this is THE A/B benchmark of the
command line.  The previous release (``--prev``, a commit) is checked out into a temporary ``git worktree``
(removed afterwards); both trees run under this interpreter and its packages (``PYTHONPATH=<tree>/src``,
``python -m auvplan``), so the comparison is of the code alone.  Each measure is the CPU time (user +
system, ``os.wait4`` of the child: not wall time) of one fresh process:

* ``--version``;
* ``validate NAME`` and ``plan NAME --json`` for every built-in scenario (a built-in newer than the release
  runs in the current tree only);
* ``data inspect FILE`` of a 1 MB NetCDF bathymetry grid written for the run (lat/lon axes, a float64
  ``elevation`` variable with CF attributes).

One warm-up run of each command per tree comes first (it writes the compiled kernels' caches), then
``auvplan kernels build`` in the current tree (the kernels the warm-ups compiled, compiled ahead of time into
one extension module: a later command runs them without importing numba; ``--no-kernels-build`` measures
numba's cache alone, each warm-up then just before its command's first measure), then ``--rounds`` rounds,
previous / current in one round and current / previous in the next, so that both see the same load; each figure is
the median over the rounds. The warm-up also fills the readers' cache (``~/.cache/auvplan/data``,
:mod:`auvplan.io.data.cache`): the figures are those of a scenario run before on the machine; its first run pays the
reading and regridding of its files once. Both trees are byte-compiled first (:func:`byte_compile`), as installing
auvplan does: an environment with ``PYTHONDONTWRITEBYTECODE=1`` (this machine's) would otherwise make every
process compile the sources again.

Beside ``plan``, the plan's own CPU: the same command run a second time inside one warm process
(``auvplan.cli.main`` twice, the second timed), so that ``plan`` CPU − own CPU is what the front door adds
(imports, first calls of compiled kernels).  Targets (issue #56): ``validate`` ≤ 1 s, ``plan`` ≤ own + 0.5 s,
``inspect`` ≤ 2 s, and current ≤ previous.  The load average is printed at the start and the end.  Exit
status 1 when a target is missed.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

OWN = r'''
import contextlib, io, json, os, sys, time
for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(var, "1")  # as the console script (auvplan.cli.main_entry) does
from auvplan.cli import main
args = json.loads(sys.argv[1])
with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
    main(args)
    c0 = time.process_time()
    main(args)
    own = time.process_time() - c0
print(json.dumps(own))
'''
"""The plan's own CPU: the command a second time in a warm process."""


def builtins(tree: Path) -> list[str]:
    """The built-in scenario names of a tree."""
    return sorted(p.stem for p in (tree / "src" / "auvplan" / "data" / "scenarios").glob("*.toml"))


def cpu_of(tree: Path, argv: list[str], timeout: float = 600.0) -> tuple[float, int]:
    """``(CPU seconds, exit code)`` of ``python -m auvplan ARGV`` importing ``tree/src`` (user + system)."""
    env = {**os.environ, "PYTHONPATH": str(tree / "src")}
    proc = subprocess.Popen([sys.executable, "-m", "auvplan", *argv], env=env, cwd=tempfile.gettempdir(),
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    t0 = time.monotonic()
    while True:
        pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
        if pid:
            break
        if time.monotonic() - t0 > timeout:
            proc.kill()
            pid, status, usage = os.wait4(proc.pid, 0)
            break
        time.sleep(0.01)
    proc.returncode = os.waitstatus_to_exitcode(status)
    return usage.ru_utime + usage.ru_stime, proc.returncode


def byte_compile(tree: Path) -> None:
    """Byte-compile ``tree/src`` into its ``__pycache__`` folders, as installing a package does (pip compiles
    every module it installs): with ``PYTHONDONTWRITEBYTECODE=1`` in the environment, Python would otherwise
    compile auvplan's ~300 modules from source in every measured process (~0.2 s of CPU no install pays)."""
    import compileall

    compileall.compile_dir(str(tree / "src"), quiet=1)


def own_cpu(tree: Path, argv: list[str]) -> float:
    """CPU of the command run a second time in one warm process (:data:`OWN`)."""
    env = {**os.environ, "PYTHONPATH": str(tree / "src")}
    out = subprocess.run([sys.executable, "-c", OWN, json.dumps(argv)], env=env, cwd=tempfile.gettempdir(),
                         capture_output=True, text=True, check=True).stdout
    return float(json.loads(out.strip().splitlines()[-1]))


def write_grid(path: Path, megabytes: float = 1.0) -> Path:
    """A NetCDF bathymetry grid of about ``megabytes`` (float64 elevation on lat/lon axes), seeded."""
    import netCDF4
    import numpy as np

    n = int((megabytes * 1e6 / 8) ** 0.5)
    lat = np.linspace(10.0, 11.0, n)
    lon = np.linspace(150.0, 151.0, n)
    rng = np.random.default_rng(0)
    z = -4000.0 + 1500.0 * np.sin(lat[:, None] * 7.0) * np.cos(lon[None, :] * 5.0) + rng.normal(0, 5, (n, n))
    with netCDF4.Dataset(path, "w") as nc:
        nc.createDimension("lat", n)
        nc.createDimension("lon", n)
        for name, values, units in (("lat", lat, "degrees_north"), ("lon", lon, "degrees_east")):
            v = nc.createVariable(name, "f8", (name,))
            v[:] = values
            v.units = units
        e = nc.createVariable("elevation", "f8", ("lat", "lon"))
        e[:] = z
        e.units, e.positive, e.standard_name = "m", "up", "height_above_mean_sea_level"
    return path


def commands(prev: Path, cur: Path, grid: Path, names: list[str] | None,
             validate_only: list[str] | None = None) -> list[tuple[str, list[str], bool]]:
    """``(label, argv, in the previous release too)`` of every measured command (``validate_only``: built-ins
    whose ``validate`` alone is measured)."""
    old = set(builtins(prev))
    out = [("--version", ["--version"], True), ("data inspect (1 MB NetCDF)", ["data", "inspect", str(grid)], True)]
    for name in names or builtins(cur):
        out.append((f"validate {name}", ["validate", name], name in old))
        out.append((f"plan {name} --json", ["plan", name, "--json"], name in old))
    out += [(f"validate {name}", ["validate", name], name in old) for name in validate_only or ()]
    return out


def build_kernels(cur: Path) -> str:
    """``auvplan kernels build`` in the current tree (the kernels the warm-ups compiled, ahead of time): its line."""
    env = {**os.environ, "PYTHONPATH": str(cur / "src")}
    r = subprocess.run([sys.executable, "-m", "auvplan", "kernels", "build"], env=env, cwd=tempfile.gettempdir(),
                       capture_output=True, text=True, timeout=1800)
    return (r.stdout or r.stderr).strip()


def measure(prev: Path, cur: Path, cmds: list[tuple[str, list[str], bool]], rounds: int,
            partial: Path | None = None, kernels: bool = True) -> dict[str, dict]:
    """Median CPU of every command in both trees over interleaved rounds, and plans' own CPU (current);
    every measure so far is written to ``partial`` (JSON) as it comes, so a time-boxed run keeps them.
    ``kernels``: every command's warm-up first, then ``auvplan kernels build`` in the current tree (a release
    before it has no such step), then the rounds."""
    runs: dict[str, dict[str, list[float]]] = {label: {"prev": [], "cur": [], "own": []} for label, _, _ in cmds}
    codes: dict[str, dict[str, int]] = {label: {} for label, _, _ in cmds}
    if kernels:
        for label, argv, both in cmds:
            for side, tree in (("prev", prev), ("cur", cur)) if both else (("cur", cur),):
                codes[label][side] = cpu_of(tree, argv)[1]
        print(f"kernels build: {build_kernels(cur)}", file=sys.stderr, flush=True)
    for k in range(rounds):
        for label, argv, both in cmds:
            if k == 0 and not kernels:  # warm-up of this command (the kernels' and readers' caches) just before it
                for side, tree in (("prev", prev), ("cur", cur)) if both else (("cur", cur),):
                    codes[label][side] = cpu_of(tree, argv)[1]
            order = (("prev", prev), ("cur", cur)) if k % 2 == 0 else (("cur", cur), ("prev", prev))
            for side, tree in order:
                if side == "cur" or both:
                    runs[label][side].append(cpu_of(tree, argv)[0])
            if argv[0] == "plan":
                runs[label]["own"].append(own_cpu(cur, argv))
            if partial is not None:
                partial.write_text(json.dumps({"round": k + 1, "runs": runs, "codes": codes,
                                               "load": os.getloadavg()[0], "nice": os.nice(0)}))
        print(f"round {k + 1}/{rounds} done (load {os.getloadavg()[0]:.1f})", file=sys.stderr, flush=True)
    return {label: {side: (statistics.median(v) if v else None) for side, v in runs[label].items()}
            | {"codes": codes[label]} for label in runs}


def _target(label: str, row: dict) -> tuple[str, bool]:
    cur, own = row["cur"], row["own"]
    if label.startswith("validate"):
        return "≤ 1 s", cur <= 1.0
    if label.startswith("plan"):
        return f"≤ own {own:.2f} + 0.5 s", cur <= own + 0.5
    if label.startswith("data inspect"):
        return "≤ 2 s", cur <= 2.0
    return "—", True


def table(rows: dict[str, dict], prev_rev: str, rounds: int, load: tuple[float, float],
          nice: int | None = None) -> tuple[str, bool]:
    """The markdown summary and whether every target (and current ≤ previous, 10 % noise) was met."""
    nice = os.nice(0) if nice is None else nice
    lines = [f"Front door against the previous release ({prev_rev}), one run (`make bench-front`): CPU (user + "
             f"system) of one fresh `python -m auvplan` process, median of {rounds} interleaved rounds after a "
             f"warm-up, both trees byte-compiled first as an install does; niceness {nice}; load average "
             f"{load[0]:.1f} at the start, {load[1]:.1f} at the end "
             "(2 cores, shared).  own = the same `plan` run again in a warm process; ratio = current / previous.", "",
             f"| command | previous ({prev_rev}) s | current s | ratio | target | met |", "|---|---|---|---|---|---|"]
    ok = True
    for label, row in rows.items():
        target, met = _target(label, row)
        prev = row["prev"]
        ratio = f"{row['cur'] / prev:.2f}" if prev else "new"
        slower = prev is not None and row["cur"] > 1.10 * prev
        bad = [c for c in row["codes"].values() if c not in (0, 1)]
        ok = ok and met and not slower and not bad
        flag = ("yes" if met else "**no**") + (" (slower)" if slower else "") + (f" (exit {bad[0]})" if bad else "")
        lines.append(f"| `{label}` | {prev:.2f} | {row['cur']:.2f} | {ratio} | {target} | {flag} |" if prev else
                     f"| `{label}` | — | {row['cur']:.2f} | {ratio} | {target} | {flag} |")
    return "\n".join(lines) + "\n", ok


def _from_partial(args: argparse.Namespace) -> int:
    """The table of the commands a time-boxed run finished (``OUT/partial.json``), in their order."""
    data = json.loads((Path(args.out) / "partial.json").read_text())
    rows = {label: {side: (statistics.median(v) if v else None) for side, v in r.items()}
            | {"codes": data["codes"][label]} for label, r in data["runs"].items() if r["cur"]}
    text, ok = table(rows, args.prev, data["round"], tuple(args.from_partial), data.get("nice"))
    done, total = len(rows), len(data["runs"])
    text = text.replace("(`make bench-front`)", f"(`make bench-front`, time-boxed: {done} of {total} commands)", 1)
    (Path(args.out) / "summary.md").write_text(text)
    if args.figure_md:
        (ROOT / "docs" / "figures" / f"{args.figure_md}.md").write_text(text)
    print(text)
    return 0 if ok else 1


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--prev", default="f5c6a15", help="the previous release's commit (default: the release)")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--scenarios", nargs="*", help="built-ins to run (default: every built-in)")
    ap.add_argument("--validate-only", nargs="*", default=[], help="built-ins whose validate alone is measured")
    ap.add_argument("--out", default="results/bench-front")
    ap.add_argument("--figure-md", default="", help="also write docs/figures/NAME.md")
    ap.add_argument("--no-kernels-build", action="store_true",
                    help="measure without kernels compiled ahead of time (numba's cache alone: AUVPLAN_AOT=0)")
    ap.add_argument("--from-partial", type=float, nargs=2, metavar=("LOAD0", "LOAD1"),
                    help="no run: the table of OUT/partial.json (a time-boxed run), the load averages given")
    args = ap.parse_args(argv)
    if args.from_partial:
        return _from_partial(args)
    if args.no_kernels_build:  # nor a module built before: numba's cache alone (auvplan.runtime.aot)
        os.environ["AUVPLAN_AOT"] = "0"
    load0 = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="auvplan-front-") as tmp:
        grid = write_grid(Path(tmp) / "grid_1mb.nc")
        wt = Path(tmp) / "prev"
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q", str(wt), args.prev], check=True)
        try:
            Path(args.out).mkdir(parents=True, exist_ok=True)
            for tree in (wt, ROOT):
                byte_compile(tree)
            rows = measure(wt, ROOT, commands(wt, ROOT, grid, args.scenarios, args.validate_only), args.rounds,
                           Path(args.out) / "partial.json", kernels=not args.no_kernels_build)
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(wt)], check=False)
    text, ok = table(rows, args.prev, args.rounds, (load0, os.getloadavg()[0]))
    text = text.replace("as an install does;", "as an install does; " + (
        "numba's cache alone (`--no-kernels-build`);" if args.no_kernels_build else
        "the current tree's kernels compiled ahead of time after the warm-up (`auvplan kernels build`);"), 1)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "summary.md").write_text(text)
    (out / "rows.json").write_text(json.dumps(rows, indent=1))
    if args.figure_md:
        (ROOT / "docs" / "figures" / f"{args.figure_md}.md").write_text(text)
    print(text)
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
