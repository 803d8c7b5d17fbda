"""Command-line front end (DESIGN.md §4): every command's arguments, the dispatch to its handler (one module
per command group: :mod:`.info`, :mod:`.plan`, :mod:`.sweep`, :mod:`.run`, :mod:`.survey`, :mod:`.results`,
:mod:`.bench`, :mod:`.serve`) and the exit codes; no logic (the jobs are in :mod:`auvplan.app`).

Exit codes: 0 success, 1 the plan/simulation failed (status not EXACT or
APPROXIMATE), 2 bad input.  ``--json`` prints exactly one JSON object on
stdout; progress and messages go to stderr.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import logging
import os
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from ..._version import __version__
from ...errors import AuvplanError, require
from .argtypes import (
    _AVOIDANCE,
    _BENCH_AVOIDANCE,
    _FORMATS,
    _PIPELINES,
    _POSITIVE,
    _RETRIES,
    _SEED,
    _WORKERS,
    _board_storage,
    _Choices,
    _departure,
    _int_at_least,
    _out_folder,
    _pitch,
    _planner_names,
    _scheduler,
    _step,
)

__all__ = ["main", "main_entry"]




_SHARED: dict[str, tuple[tuple[str, ...], dict[str, Any]]] = {
    "scenario": (("scenario",), {"help": "TOML file or built-in scenario name"}),
    "planner": (("--planner",), {"choices": _Choices(_planner_names), "metavar": "PLANNER",
                                 "help": "override the scenario's planner: %(choices)s"}),
    "guidance": (("--guidance",), {"choices": ("hybrid", "los", "ilos"), "help": "override the scenario's guidance"}),
    "avoidance": (("--avoidance",), {"choices": _AVOIDANCE, "metavar": "AVOIDANCE",
                                     "help": "override the scenario's avoidance: %(choices)s"}),
    "seed": (("--seed",), {"type": _SEED, "help": "random seed >= 0 (default: the scenario's)"}),
    "full": (("--full",), {"action": "store_true",
                           "help": "tracks at full resolution (default: every 20 m / 30 s)"}),
    "force": (("--force",), {"action": "store_true",
                             "help": "overwrite files in the results folder (--out or DIR) not written by auvplan"}),
    "json": (("--json",), {"action": "store_true", "help": "print one JSON object on stdout"}),
    "dir": (("dir",), {"help": "results directory written by `auvplan run --out` or `demo`"}),
    "board_storage": (("--board-storage",), {
        "type": _board_storage, "metavar": "16k|32k|sd:N",
        "help": "the vehicle's mission storage: 16k (655 commands), 32k (FRAM, 1312) or sd:N (BRD_SD_MISSION = N "
                "KiB, at most 64: 4368); a .plan it cannot hold fails (default: only one over 4368, which no board "
                "holds)"}),
}
"""Arguments several commands share, by name (same flag, same meaning, same help everywhere)."""


def _shared(s: Any, *keys: str) -> None:
    """Add the shared arguments ``keys`` (in that order) to the (sub-)parser ``s``."""
    for key in keys:
        flags, kwargs = _SHARED[key]
        s.add_argument(*flags, **kwargs)


def _cluster(s: Any, workers: int | None) -> None:
    """``--workers N | --scheduler ADDR`` and ``--retries N``: where a job's independent tasks run
    (:mod:`auvplan.runtime.parallel`; ``workers`` None: in this process unless one is given)."""
    g = s.add_mutually_exclusive_group()
    g.add_argument("--workers", type=_WORKERS, default=workers,
                   help="local dask worker processes (a LocalCluster)"
                        + (f"; default {workers}" if workers else "; default: this process, no dask"))
    g.add_argument("--scheduler", type=_scheduler,
                   help="address of a running dask scheduler, e.g. tcp://host:8786 (docs/parallel.md)")
    s.add_argument("--retries", type=_RETRIES, default=1, help="runs again of a task that fails (default 1)")


def _command(sub: Any, name: str, help: str, func: str, *shared: str) -> Any:
    """A sub-command with the shared arguments ``shared`` (in that order) and its handler ``func``, named
    ``"<module>:<function>"`` in a command group's module of :mod:`auvplan.cli` (imported when a command runs, so
    ``--help`` and ``--version`` import nothing of the library)."""
    s = sub.add_parser(name, help=help)
    _shared(s, *shared)
    _chatter(s, argparse.SUPPRESS)  # also after the command (`auvplan run X -q`); absent there: the top level's
    s.set_defaults(func=func)
    return s


def _chatter(p: argparse.ArgumentParser, default: Any) -> None:
    """``-v``/``--verbose`` and ``-q``/``--quiet`` on ``p`` (each command's with ``default`` ``SUPPRESS``, so that
    a flag given before the command is not reset by the command's parser)."""
    p.add_argument("-v", "--verbose", action="store_true", default=default, help="log progress details to stderr")
    p.add_argument("-q", "--quiet", action="store_true", default=default,
                   help="no progress bars or stage lines on stderr")


def _info_commands(sub: Any) -> None:
    """``scenarios``, ``validate``, ``data inspect``, ``scenario new|schema``."""
    _command(sub, "scenarios", "list the built-in scenarios", "info:cmd_scenarios")
    _command(sub, "validate", "check a scenario file (exit 2 with clear messages)", "info:cmd_validate", "scenario")
    s = sub.add_parser("data", help="inspect bathymetry and current files (NetCDF, GeoTIFF)")
    dsub = s.add_subparsers(dest="data_command", required=True)
    d = _command(dsub, "inspect", "print the layout, variables, units and axes auvplan detects in FILE",
                 "info:cmd_data_inspect")
    d.add_argument("file", help="NetCDF or GeoTIFF file")
    s = sub.add_parser("scenario", help="scenario format tools: a commented template, the JSON Schema")
    ssub = s.add_subparsers(dest="scenario_command", required=True)
    t = _command(ssub, "new", "write a commented scenario template (to FILE, or stdout)", "info:cmd_scenario_new")
    t.add_argument("file", nargs="?", help="the new scenario file (refused if it exists, unless --force)")
    t.add_argument("--force", action="store_true", help="overwrite an existing FILE")
    _command(ssub, "schema", "print the scenario format's versioned JSON Schema", "info:cmd_scenario_schema")


def _flight_commands(sub: Any) -> None:
    """``plan``, ``simulate``, ``run``."""
    s = _command(sub, "plan", "plan a global path", "plan:cmd_plan", "scenario", "planner", "seed")
    s.add_argument("--budget", type=_POSITIVE, help="objective evaluations, spent exactly by every optimiser")
    s.add_argument("--pipeline", choices=_PIPELINES, metavar="PIPELINE",
                   help=("seeded (lattice seeds + refinement + fallback, default), document (the algorithm "
                         "alone) or progressive (alone, coarse to fine)"))
    s.add_argument("--reference", action="store_true",
                   help="also plan the grid reference and report reference_cost and gap_pct")
    s.add_argument("--out", type=_out_folder, help="write metrics.json, path.csv and the scenario here")
    _shared(s, "force", "json")
    s.add_argument("--depart-between", nargs=2, metavar=("T0", "T1"), type=_departure,
                   help="sweep the departure time (ISO 8601 UTC, or +6h after [mission] start_time) with the "
                        "time-dependent planner; writes sweep.csv, sweep_summary.json and sweep.png to --out")
    s.add_argument("--step", default="15min", type=_step, help="departure step of the sweep (default 15min)")
    s.add_argument("--objective", choices=("time", "energy"), help="objective of the sweep's timed plans")
    _cluster(s, None)  # the sweep's departures, the robust plan's candidates

    s = _command(sub, "simulate", "simulate the vehicle flying the route (or the mission of the plan), as `run`",
                 "plan:cmd_simulate", "scenario", "guidance", "avoidance", "seed")
    s.add_argument("--out", type=_out_folder, help="write sim_metrics.json and track.csv here")
    _shared(s, "full", "force", "json")

    s = _command(sub, "run", "plan + key waypoints + closed-loop simulation with moving obstacles", "run:cmd_run",
                 "scenario", "planner", "guidance", "avoidance", "seed")
    s.add_argument("--out", type=_out_folder, help="write every result file here")
    _shared(s, "full", "force", "json", "board_storage")

    s = _command(sub, "survey", "plan, fly and measure the [survey] of a scenario: depth-adaptive lines, flyable "
                 "turns, coverage (lines.csv, coverage.json, coverage.png, mission exports)", "survey:cmd_survey",
                 "scenario", "guidance", "seed")
    s.add_argument("--out", type=_out_folder,
                   help="write lines.csv, coverage.json, gaps.geojson, coverage.png and the exports here")
    _shared(s, "full", "force", "json", "board_storage")
    _cluster(s, None)


def _result_commands(sub: Any) -> None:
    """``report``, ``export``, ``mission check``."""
    s = _command(sub, "report", "write report.html (and the exports) for a results directory of `run --out`",
                 "results:cmd_report", "dir")
    s.add_argument("--figures", action="store_true", help="also write static PNG/SVG figures into DIR/figures")
    _shared(s, "force", "board_storage")
    s = _command(sub, "export", "write mission exports (GeoJSON, KML, CSV, MOOS-IvP, QGC .plan, GPX, ROS 2 "
                                "nav_msgs/Path YAML) for a results directory", "results:cmd_export", "dir")
    s.add_argument("--format", nargs="+", default=_FORMATS, choices=_FORMATS, metavar="FORMAT",
                   help="mission formats (default: all): %(choices)s")
    _shared(s, "full", "force", "board_storage")
    s = sub.add_parser("mission", help="work with exported mission files")
    msub = s.add_subparsers(dest="mission_command", required=True)
    c = _command(msub, "check", "re-fly mission files under their format's depth semantics against the "
                                "scenario's seabed, static obstacles, sea surface, depth band and bounds, and "
                                "check the [vehicle]'s pitch, turn radius and depth rating (exit 1 when one is "
                                "broken)",
                 "results:cmd_mission_check")
    c.add_argument("files", nargs="+", help="mission.moos / .plan / .gpx / .yaml / .geojson / .kml / .csv")
    c.add_argument("--scenario", required=True, help="TOML file or built-in scenario name")
    c.add_argument("--pitch", type=_pitch, default=15.0,
                   help="pitch (deg) at which a depth-holding executor (MOOS) changes depth (default 15)")
    c.add_argument("--json", action="store_true", help="print one JSON object (a list for several files)")
    _shared(c, "board_storage")


def _serve_command(sub: Any) -> None:
    """``serve``: the local planning page (:mod:`auvplan.cli.serve`)."""
    s = _command(sub, "serve", "plan, edit and check a mission in a local web page (offline)", "serve:cmd_serve")
    s.add_argument("target", nargs="?", metavar="SCENARIO | RESULTS_DIR",
                   help="built-in name, TOML file or results folder (default: the built-in showcase)")
    s.add_argument("--port", type=_int_at_least(0, 65535), default=8765,
                   help="TCP port (default 8765; 0: any free port)")
    s.add_argument("--host", default="127.0.0.1", help="address to serve on (default 127.0.0.1: this machine only)")
    s.add_argument("--root", action="append", metavar="DIR",
                   help="a folder the page may read and save in (repeatable; default: the folder of the "
                        "scenario or the results folder, else the current folder)")
    s.add_argument("--no-browser", action="store_true", help="do not open the page in the browser")


def _kernels_command(sub: Any) -> None:
    """``kernels build``: the kernels compiled ahead of time (:mod:`auvplan.cli.info`)."""
    s = sub.add_parser("kernels", help="compile the kernels ahead of time: commands then start without numba")
    ksub = s.add_subparsers(dest="kernels_command", required=True)
    b = _command(ksub, "build", "compile every kernel numba has compiled here (after planning each SCENARIO) into "
                 "one extension module (a C compiler is needed; without one, numba as before)",
                 "info:cmd_kernels_build")
    b.add_argument("scenarios", nargs="*", metavar="SCENARIO", help="built-in names or TOML files to plan first")


def _bench_commands(sub: Any) -> None:
    """``bench`` and ``demo``."""
    s = _command(sub, "bench", "sweep scenarios x planners x guidance x seeds on dask (rows.csv + summary)",
                 "bench:cmd_bench")
    s.add_argument("--scenarios", nargs="+", default=["dynamic-terrain"], help="built-in names or TOML files")
    s.add_argument("--planners", nargs="+", default=["scenario"],
                   help="planner names, or 'scenario'; name/pipeline picks the pipeline (iabc/progressive)")
    s.add_argument("--guidance", nargs="+", default=["scenario"], help="hybrid, los, ilos, or 'scenario'")
    s.add_argument("--seeds", type=_POSITIVE, default=10, help="seeds 0..N-1 per cell")
    s.add_argument("--budget", type=_SEED, default=0, help="objective evaluations per plan (0: the scenario's)")
    s.add_argument("--reference", action="store_true", help="add the gap to the grid reference to every row")
    s.add_argument("--randomise", action="store_true", help="re-draw the moving obstacles' tracks per seed")
    s.add_argument("--plan-once", action="store_true", help="plan once per cell, fly it in every seed")
    s.add_argument("--avoidance", nargs="+", default=["scenario"], choices=_BENCH_AVOIDANCE, metavar="AVOIDANCE",
                   help="local avoidance variants (an axis; 'scenario' = the scenario's own): %(choices)s")
    s.add_argument("--members", nargs="+", default=["scenario"], metavar="MEMBER",
                   help="current ensemble members as an axis: names from [currents] members, 'each', or 'scenario'")
    s.add_argument("--member-seeds", nargs="+", type=_SEED, default=[], metavar="SEED",
                   help="re-draw the [currents] members' perturbation entries with each seed (an axis)")
    s.add_argument("--chunk", type=_POSITIVE, default=10, help="seeds per dask task")
    _cluster(s, 2)
    s.add_argument("--resume", action="store_true", help="complete an interrupted sweep in --out")
    s.add_argument("--out", type=_out_folder, default="results/bench",
                   help="folder of rows.csv, summary.csv/md and figures")
    _shared(s, "force")
    s = _command(sub, "demo", "run the built-in default scenario (showcase) end to end", "run:cmd_demo")
    s.add_argument("--out", type=_out_folder, default="auvplan-demo", help="results directory (default: auvplan-demo)")
    _shared(s, "force")


class _Parser(argparse.ArgumentParser):
    """argparse's parser, except that ``--help`` or ``--version`` into a stdout that cannot be written is an error
    (argparse ignores it: ``auvplan --help > /dev/full`` exited 0, silent)."""

    def _print_message(self, message: str, file: Any = None) -> None:
        if not message:
            return
        file = file or sys.stderr
        try:
            file.write(message)
        except OSError:
            if file is sys.stdout:  # :func:`.output.named_stdout` names it
                raise


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="auvplan", description="Plan, check and simulate 3D AUV missions.")
    p.add_argument("--version", action="version", version=f"auvplan {__version__}")
    _chatter(p, False)
    sub = p.add_subparsers(dest="command", required=True)
    _info_commands(sub)
    _flight_commands(sub)
    _result_commands(sub)
    _bench_commands(sub)
    _serve_command(sub)
    _kernels_command(sub)
    return p


def main(argv: list[str] | None = None) -> int:
    """Run the command line.

    Parameters
    ----------
    argv : list of str, optional
        The arguments (``sys.argv[1:]`` by default).

    Returns
    -------
    int
        The exit code: 0 success, 1 a mission or plan that failed (a status), 2 bad input or a
        missing optional dependency (one line on stderr), 130 interrupted, 141 stdout's reader gone (``| head``).
    """
    from ..output import StdoutError, named_stdout

    parser = _parser()
    try:
        with named_stdout():  # --help, --version
            args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse exits 2 on bad usage, 0 on --help
        return int(exc.code or 0)
    except StdoutError as exc:
        return _stdout_lost(exc)
    from ...io.files import manifest, safeio

    undo: Callable[[], None] = _nothing
    if getattr(args, "json", False):  # issue 51: warnings go into the JSON object, stderr stays empty on success
        undo = _collect_warnings()
    else:
        from ..output import LogLines  # on stderr above the live line (issue 56), never onto a drawn clock

        logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING, handlers=[LogLines()],
                            format="%(levelname)s %(name)s: %(message)s")
    try:
        if _writes_html(args):  # checked before any work is done
            require("plotly", "report")
        if args.command in _CLOCKED and not (args.quiet or getattr(args, "json", False)):
            from ..output import starting

            starting(f"{args.command}: starting")  # issue 56: a clock from the first second (the imports)
        module, _, name = args.func.partition(":")  # "<command group module>:<handler>"
        handler = getattr(importlib.import_module(f"auvplan.cli.{module}"), name)
        from ...io.files import safeio
        with safeio.session(), named_stdout():  # the --out folders released, what a failure made removed; stdout
            code: int = handler(args)  # named when it cannot be written (> /dev/full)
        return code
    except KeyboardInterrupt:
        out = getattr(args, "out", None)
        partial = isinstance(out, str) and bool(manifest.written(Path(out)))  # none: what it made there is gone
        _last_line(f"auvplan: interrupted; partial results in {out}" if partial else "auvplan: interrupted; "
                   f"nothing written{f' into {out}' if out else ''}")
        return 130
    except BrokenPipeError:  # the reader went away (`auvplan scenarios | head -1`): nothing to say, as a tool
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # killed by SIGPIPE; the flush at exit
        return 141  # writes to /dev/null (128 + SIGPIPE, as 130 is 128 + SIGINT)
    except StdoutError as exc:
        return _stdout_lost(exc)
    except (AuvplanError, ValueError, OSError, MemoryError, RecursionError) as exc:
        _last_line(f"auvplan: error: {_one_line(exc)}")
        return 2
    finally:
        undo()
        from ..output import finish

        finish()  # the live progress line (issue 56)


_CLOCKED = ("plan", "simulate", "run", "survey", "report", "export", "demo")
"""The commands whose stages show on stderr (:mod:`.output`): a clock runs from their start."""


def _stdout_lost(exc: BaseException) -> int:
    """Stdout cannot be written: say so on stderr (exit 2); what it still buffers goes to /dev/null, not to a second
    error when Python flushes it at exit."""
    with contextlib.suppress(OSError, ValueError, AttributeError):  # a stream without a descriptor: nothing to do
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    _last_line(f"auvplan: error: {exc}")
    return 2


def _nothing() -> None:
    """Nothing to undo."""


def _last_line(text: str) -> None:
    """The command's last line on stderr, on a line of its own: the live line (a stage's clock drawn after a
    silence) is ended first, not written onto."""
    from ..output import finish

    finish()
    print(text, file=sys.stderr)


def _collect_warnings() -> Callable[[], None]:
    """Send logging warnings and Python warnings of a ``--json`` command to the JSON object's ``warnings``
    (:data:`auvplan.cli.output.JSON_WARNINGS`) instead of stderr; returns what undoes it."""
    import warnings

    from ..output import JSON_WARNINGS

    JSON_WARNINGS.clear()

    class _Collect(logging.Handler):
        def emit(self, record: logging.LogRecord) -> None:
            JSON_WARNINGS.append(f"{record.name}: {record.getMessage()}")

    root, handler, shown, level = logging.getLogger(), _Collect(logging.WARNING), warnings.showwarning, None
    level = root.level
    root.addHandler(handler)
    root.setLevel(min(level or logging.WARNING, logging.WARNING))

    def show(message: Warning | str, category: type[Warning], *rest: Any, **kw: Any) -> None:
        JSON_WARNINGS.append(f"{category.__name__}: {message}")

    warnings.showwarning = show

    def undo() -> None:
        root.removeHandler(handler)
        root.setLevel(level)
        warnings.showwarning = shown

    return undo


def _writes_html(args: argparse.Namespace) -> bool:
    """Whether the command writes an HTML report (plotly, the ``report`` extra)."""
    return args.command in ("demo", "report", "bench") or (args.command == "run" and bool(args.out))


def _one_line(exc: BaseException) -> str:
    """The exception as one line (multi-line library messages folded); the type when it has no text."""
    text = " ".join(str(exc).split())
    if isinstance(exc, MemoryError):
        return f"out of memory ({text or 'MemoryError'}); lower the sizes, or check [limits] memory_mb"
    if isinstance(exc, AuvplanError) and text:
        return text
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def main_entry() -> None:
    """Console-script entry point.

    Once the command has returned, its output flushed and the exit handlers run, the process ends without
    tearing down the ~2 000 modules a planning command imports (issue 56: that took 0.3-3 s of CPU after the
    last line, silent) — unless a thread other than daemons still runs or a profiler or tracer (cProfile,
    coverage) is on, when Python ends as usual.

    One BLAS/OpenMP thread unless the environment asks for more (``OPENBLAS_NUM_THREADS`` …, set before
    numpy loads): OpenBLAS's idle workers spin, and on a busy machine a small LAPACK call (the Delaunay
    weights of a curvilinear current file, 196 nodes) cost 0.7-1.5 s of CPU with them, 0.002 s without.
    """
    for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(var, "1")
    code = main()
    import atexit
    import threading

    others = any(not t.daemon for t in threading.enumerate() if t is not threading.main_thread())
    if others or sys.getprofile() is not None or sys.gettrace() is not None:
        sys.exit(code)
    atexit._run_exitfuncs()
    logging.shutdown()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


if __name__ == "__main__":  # pragma: no cover
    main_entry()
