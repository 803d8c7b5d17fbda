"""Mutation testing of the safety-relevant functions: a small AST mutation driver.

Usage::

    .venv/bin/python tools/mutate.py [MODULE ...] [--list] [--only N,M] [--timeout S] [--out DIR]

(``make mutants`` runs every module).  For each module the named functions are parsed, every
mutation site in their bodies is enumerated (operators below), and each mutant is run against the
module's tests; a JSON record per module goes to ``build/mutants/`` and a summary table to stdout.

Which tests: a target that names none (``Target.tests`` empty) is run against **every test file
that imports a mutated module** (:func:`importing_tests`: an ``import``/``from ... import`` of the
module itself, or of a name it defines through a package re-export, anywhere in the file), all of
each file's tests.  One rule keeps that affordable on a shared machine: a test whose *unmutated* run
uses more than ``--test-limit`` CPU seconds (default 30) is dropped from the selection, and the
record lists it (``slow``) -- a mutant is then a survivor only if all the remaining tests pass.
Tests run fastest first with ``-x`` semantics, and each test that kills a mutant moves to the front
for the next ones (mutants of one line tend to fall to the same test), so a killed mutant costs little.

Why not mutmut: mutmut 2 starts a fresh Python per mutant (importing numpy, scipy, numba, xarray:
~5-10 s on a loaded machine) and, for the kernel modules, recompiled every numba kernel per
mutant, so only 19 mutants ran in half an hour.  Here:

* where the mutated functions are numba kernels (terrain, cost, grid) the kernels run as plain
  Python (``NUMBA_DISABLE_JIT=1``, set before numba is imported): no compilation at all, and the
  selected tests use small inputs; elsewhere the kernels are compiled (or loaded from the cache)
  once, by the unmutated run in the parent, and every child inherits them;
* the parent imports auvplan and the tests once, then **forks** one child per mutant; the child
  swaps the mutated function's code object into the live function (``f.__code__ = ...``: every
  reference, including ``from module import kernel`` elsewhere, sees the mutant), runs
  ``pytest -x`` on the selection and exits.  Nothing is written to the source tree.
* a child that has used more CPU time than the timeout (3x the unmutated run's; CPU, not wall time, as
  the machine may be loaded) is killed and counted as ``timeout``, separately; so is one that has run longer
  than the wall-clock limit (``--wall``, default 10x the CPU timeout and at least 120 s): a mutant that makes a
  test wait for ever (a lock, an event, a pipe, a subprocess that hangs) uses no CPU and stalled the run.  Each
  child leads its own process group and the whole group is killed (a test's hung subprocess too); the record
  says which limit (``timeout``: ``"cpu"`` or ``"wall"``), and the report counts the wall-clock ones apart.

Operators (one change per mutant, AST level, in function bodies only; docstrings, annotations,
default values, ``raise``/``assert`` statements and f-strings are left alone):

``arith``   ``+ ↔ -``, ``* ↔ /``, ``// → /``, ``% → /``, ``** → *`` (also in ``x op= y``)
``cmp``     ``< ↔ <=``, ``> ↔ >=``, ``== ↔ !=`` (boundary) and ``< → >=``, ``<= → >``, ``> → <=``,
            ``>= → <`` (negation); ``is ↔ is not``, ``in ↔ not in``
``bool``    ``and ↔ or``; ``not x → x``; ``True ↔ False``
``unary``   ``-x → x``
``number``  ``n → n + 1`` (ints and floats; ``0.5 → 1.5``, ``1e-9 → 1.000000001``)
``call``    ``min ↔ max``, ``np.minimum ↔ np.maximum``, ``np.min ↔ np.max``, ``np.any ↔ np.all``,
            ``argmin ↔ argmax``, ``abs(x) → x``
``flow``    ``break ↔ continue``
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("MPLBACKEND", "Agg")

import argparse  # noqa: E402
import ast  # noqa: E402
import contextlib  # noqa: E402
import copy  # noqa: E402
import importlib  # noqa: E402
import inspect  # noqa: E402
import json  # noqa: E402
import random  # noqa: E402
import resource  # noqa: E402
import signal  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import textwrap  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from dataclasses import asdict, dataclass  # noqa: E402
from pathlib import Path  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
sys.path.insert(0, str(ROOT / "tools"))
sys.path.append(str(ROOT))  # as `python -m pytest` from the root: tests that import benchmarks/

from mutation_targets import LISTED, MODULES, REASONS  # noqa: E402

# ---------------------------------------------------------------------------------------- operators
_ARITH: dict[type, tuple[type, ...]] = {
    ast.Add: (ast.Sub,), ast.Sub: (ast.Add,), ast.Mult: (ast.Div,), ast.Div: (ast.Mult,),
    ast.FloorDiv: (ast.Div,), ast.Mod: (ast.Div,), ast.Pow: (ast.Mult,),
}
_CMP: dict[type, tuple[type, ...]] = {
    ast.Lt: (ast.LtE, ast.GtE), ast.LtE: (ast.Lt, ast.Gt), ast.Gt: (ast.GtE, ast.LtE), ast.GtE: (ast.Gt, ast.Lt),
    ast.Eq: (ast.NotEq,), ast.NotEq: (ast.Eq,), ast.Is: (ast.IsNot,), ast.IsNot: (ast.Is,),
    ast.In: (ast.NotIn,), ast.NotIn: (ast.In,),
}
_NAMES = {"min": "max", "max": "min", "minimum": "maximum", "maximum": "minimum", "amin": "amax", "amax": "amin",
          "any": "all", "all": "any", "argmin": "argmax", "argmax": "argmin", "nanmin": "nanmax", "nanmax": "nanmin"}
_SKIP = (ast.Raise, ast.Assert, ast.JoinedStr, ast.arguments)


def _walk(node: ast.AST) -> list[ast.AST]:
    """Nodes of a function body in a fixed order, leaving out what is not mutated."""
    out: list[ast.AST] = []

    def visit(n: ast.AST) -> None:
        if isinstance(n, _SKIP):
            return
        out.append(n)
        for field, value in ast.iter_fields(n):
            if field in ("decorator_list", "returns", "annotation", "type_comment"):
                continue
            items = value if isinstance(value, list) else [value]
            for i, item in enumerate(items):
                if not isinstance(item, ast.AST):
                    continue
                if field == "body" and i == 0 and isinstance(n, (ast.FunctionDef, ast.ClassDef)) \
                        and isinstance(item, ast.Expr) and isinstance(item.value, ast.Constant) \
                        and isinstance(item.value.value, str):
                    continue  # docstring
                visit(item)

    visit(node)
    return out


def _ops(node: ast.AST) -> list[tuple[str, object]]:
    """The mutations of one node: (operator family, payload)."""
    out: list[tuple[str, object]] = []
    if isinstance(node, (ast.BinOp, ast.AugAssign)):
        out += [("arith", new) for new in _ARITH.get(type(node.op), ())]
    elif isinstance(node, ast.Compare):
        for k, op in enumerate(node.ops):
            out += [("cmp", (k, new)) for new in _CMP.get(type(op), ())]
    elif isinstance(node, ast.BoolOp):
        out.append(("bool", ast.Or if isinstance(node.op, ast.And) else ast.And))
    elif isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.Not, ast.USub)):
        out.append(("unary", None))
    elif isinstance(node, ast.Constant):
        if isinstance(node.value, bool):
            out.append(("bool", not node.value))
        elif isinstance(node.value, (int, float)):
            out.append(("number", node.value + 1))
    elif isinstance(node, ast.Call):
        f = node.func
        name = f.id if isinstance(f, ast.Name) else f.attr if isinstance(f, ast.Attribute) else None
        if name in _NAMES:
            out.append(("call", _NAMES[name]))
        if isinstance(f, ast.Name) and f.id == "abs" and len(node.args) == 1:
            out.append(("call", None))
    elif isinstance(node, ast.Break):
        out.append(("flow", ast.Continue))
    elif isinstance(node, ast.Continue):
        out.append(("flow", ast.Break))
    return out


def _apply(node: ast.AST, kind: str, payload: object) -> ast.AST | None:
    """Mutate ``node`` in place; return a replacement node when the node itself is replaced."""
    if kind == "arith":
        node.op = payload()  # type: ignore[attr-defined,operator]
    elif kind == "cmp":
        k, new = payload  # type: ignore[misc]
        node.ops[k] = new()  # type: ignore[attr-defined]
    elif kind == "bool" and isinstance(node, ast.BoolOp):
        node.op = payload()  # type: ignore[operator]
    elif kind in ("bool", "number"):
        node.value = payload  # type: ignore[attr-defined]
    elif kind == "unary":
        return node.operand  # type: ignore[attr-defined]
    elif kind == "call":
        if payload is None:
            return node.args[0]  # type: ignore[attr-defined]
        f = node.func  # type: ignore[attr-defined]
        if isinstance(f, ast.Name):
            f.id = payload
        else:
            f.attr = payload
    elif kind == "flow":
        return payload()  # type: ignore[operator]
    return None


# ---------------------------------------------------------------------------------------- mutants
@dataclass
class Mutant:
    """One single-site change of one function."""

    id: int
    module: str
    function: str
    line: int
    kind: str
    before: str
    after: str
    status: str = "not run"
    seconds: float = 0.0
    end_line: int = 0  # the changed node's last line (the node spans line..end_line)
    first_line: int = 0  # the first line of the statement holding the node (0: ``line``): the tracer's span
    tests_run: int = -1  # how many tests covered the changed lines (-1: the whole selection, no coverage)
    timeout: str = ""  # which limit killed it: "cpu" or "wall" (status "timeout")


def _function_node(tree: ast.Module, qualname: str) -> ast.FunctionDef:
    node: ast.AST = tree
    for part in qualname.split("."):
        node = next(c for c in ast.iter_child_nodes(node)
                    if isinstance(c, (ast.FunctionDef, ast.ClassDef)) and c.name == part)
    assert isinstance(node, ast.FunctionDef)
    return node


def _live_function(module: object, qualname: str):
    """The function object whose ``__code__`` runs for ``qualname`` (through property, staticmethod,
    functools wrappers and numba dispatchers)."""
    obj: object = module
    parts = qualname.split(".")
    for part in parts[:-1]:
        obj = getattr(obj, part)
    f = obj.__dict__[parts[-1]] if isinstance(obj, type) else getattr(obj, parts[-1])
    for attr in ("fget", "__func__", "py_func", "__wrapped__"):
        while hasattr(f, attr) and not inspect.isfunction(f):
            f = getattr(f, attr)
    f = inspect.unwrap(f)
    assert inspect.isfunction(f), qualname
    return f


def _snippet(node: ast.AST) -> str:
    text = ast.unparse(node)
    return text if len(text) <= 90 else text[:87] + "..."


def _span(fn: ast.FunctionDef, source: str, spec: tuple[str, ...]) -> tuple[int, int]:
    """Lines of ``fn`` to mutate: all of it, or from the line holding marker ``spec[2]`` up to (not
    including) the line holding ``spec[3]``."""
    if len(spec) < 4:
        return fn.lineno, fn.end_lineno or fn.lineno
    lines = source.splitlines()
    inside = range(fn.lineno - 1, fn.end_lineno or len(lines))
    start = next(i for i in inside if spec[2] in lines[i]) + 1
    end = next(i for i in inside if i >= start and spec[3] in lines[i]) + 1
    return start, end - 1


def _statement_starts(fn: ast.FunctionDef) -> dict[int, int]:
    """For each expression node of ``fn`` (by ``id``), the first line of its innermost statement.  A constant
    tuple over several lines is one ``LOAD_CONST`` carrying its statement's first line (mutants20: ``_station``'s
    ``for key, lo, hi in ((...), (...), ...)``): the tracer never sees the lines of its later elements, so the
    tests that run a mutant there are those that run its statement."""
    out: dict[int, int] = {}

    def visit(n: ast.AST, start: int) -> None:
        if isinstance(n, ast.stmt):
            start = n.lineno
        out[id(n)] = start
        for child in ast.iter_child_nodes(n):
            visit(child, start)

    visit(fn, fn.lineno)
    return out


def generate(trees: dict[str, ast.Module], functions: tuple[tuple[str, ...], ...],
             sources: dict[str, str] | None = None) -> list[tuple[Mutant, int, int]]:
    """Every mutant of the named functions (or of their marked parts): (record, node index, operation index)."""
    out = []
    seen: set[tuple[str, str]] = set()
    for spec in functions:
        modname, name = spec[0], spec[1]
        fn = _function_node(trees[modname], name)
        lo, hi = _span(fn, (sources or {}).get(modname, ""), spec)
        original = ast.unparse(fn)
        starts = _statement_starts(fn)
        for i, node in enumerate(_walk(fn)):
            line = getattr(node, "lineno", fn.lineno)
            if not lo <= line <= hi:
                continue
            for j, (kind, _payload) in enumerate(_ops(node)):
                new_fn, new_node = _mutated(fn, i, j)
                source = ast.unparse(new_fn)
                if source == original or (name, source) in seen:
                    continue  # no change, or a duplicate of an earlier mutant
                seen.add((name, source))
                m = Mutant(len(out) + 1, modname, name, line, kind, _snippet(node), _snippet(new_node),
                           end_line=getattr(node, "end_lineno", None) or line, first_line=starts.get(id(node), line))
                out.append((m, i, j))
    return out


def _mutated(fn: ast.FunctionDef, i: int, j: int) -> tuple[ast.FunctionDef, ast.AST]:
    """A copy of ``fn`` with operation ``j`` of its ``i``-th node applied, and the changed node."""
    new_fn = copy.deepcopy(fn)
    nodes = _walk(new_fn)
    node = nodes[i]
    kind, payload = _ops(node)[j]
    replacement = _apply(node, kind, payload)
    if replacement is not None:
        _replace(new_fn, node, replacement)
        return new_fn, replacement
    return new_fn, node


def _replace(root: ast.AST, old: ast.AST, new: ast.AST) -> None:
    for parent in ast.walk(root):
        for field, value in ast.iter_fields(parent):
            if value is old:
                setattr(parent, field, new)
                return
            if isinstance(value, list):
                for k, item in enumerate(value):
                    if item is old:
                        value[k] = new
                        return
    raise AssertionError("node not found")


def _install(module: object, fn_node: ast.FunctionDef, qualname: str) -> None:
    """Compile ``fn_node`` in ``module``'s namespace and swap its code into the live function."""
    live = _live_function(module, qualname)
    node = copy.deepcopy(fn_node)
    node.decorator_list = []
    freevars = live.__code__.co_freevars
    if freevars:  # e.g. ``__class__`` of zero-argument super(): compile inside a closure with those cells
        outer = ast.parse(f"def __mutant_outer__({', '.join(freevars)}):\n    pass\n").body[0]
        assert isinstance(outer, ast.FunctionDef)
        outer.body = [node, ast.Return(ast.Name(node.name, ast.Load()))]
        tree = ast.Module([outer], [])
    else:
        tree = ast.Module([node], [])
    ast.fix_missing_locations(tree)
    namespace: dict[str, object] = {}
    exec(compile(tree, inspect.getfile(live), "exec"), vars(module), namespace)  # noqa: S102
    new = namespace[node.name] if not freevars else namespace["__mutant_outer__"](*[None] * len(freevars))
    live.__code__ = new.__code__  # type: ignore[attr-defined]


# ---------------------------------------------------------------------------------------- runner
class _TooSlow(Exception):
    """Raised in a test of the unmutated run that used more than the per-test CPU limit."""


_KILLER_CODES = 250
"""A child's exit code ``1 + k`` (``k < 250``) names the test ``items[k]`` that killed the mutant; 255:
the mutant broke the test machinery."""

_SLOW: dict[str, list[str]] = {}
"""Per target, the tests dropped from its selection as too slow (the unmutated run's ``slow``)."""


def importing_tests(modules: list[str] | tuple[str, ...], tests_dir: Path = ROOT / "tests") -> list[str]:
    """The test files that import one of ``modules``: directly, or a name one of them defines
    through a package (``from auvplan.world import World`` imports ``auvplan.world.world``), at any
    level of the file (local imports inside tests count)."""
    wanted, out = set(modules), []
    for path in sorted(tests_dir.rglob("test_*.py")):
        found: set[str] = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                found |= {a.name for a in node.names}
            elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0 \
                    and node.module.split(".")[0] == "auvplan":
                found.add(node.module)
                package = importlib.import_module(node.module)
                for a in node.names:
                    obj = getattr(package, a.name, None)
                    found.add(obj.__name__ if inspect.ismodule(obj) else getattr(obj, "__module__", None) or "")
        if found & wanted:
            out.append(str(path.relative_to(ROOT)))
    return out


def _codes(fn: object) -> set:
    """The code object of function ``fn`` and every code object nested in it (comprehensions, lambdas,
    inner functions: in Python 3.11 each is its own code object)."""
    out, todo = set(), [fn.__code__]  # type: ignore[attr-defined]
    while todo:
        code = todo.pop()
        out.add(code)
        todo += [c for c in code.co_consts if inspect.iscode(c)]
    return out


class _Coverage:
    """Which lines of the mutated functions each test executes (``sys.settrace``, local tracing only
    inside those functions' code objects, in every thread started while it is on).  A mutant changes one
    node spanning lines ``line..end_line``; a test that executes none of those lines runs the mutant
    exactly as the original (the rest of the code object is the same), so it cannot kill it and is not run.

    Sound for Python >= 3.11: each bytecode of the node carries a line of the node's span and the tracer
    sees a ``line`` event whenever the executing line changes, so any execution of the node records a
    line in its span."""

    def __init__(self, codes: set) -> None:
        self.codes, self.current = codes, ""
        self.lines: dict[str, set[tuple[str, int]]] = {}
        self.unknown: set[str] = set()  # tests during which the tracer was switched off: run for every mutant

    def _local(self, frame, event: str, _arg):  # noqa: ANN001, ANN202
        if event == "line":
            self.lines.setdefault(self.current, set()).add((frame.f_code.co_filename, frame.f_lineno))
        return self._local

    def _global(self, frame, event: str, _arg):  # noqa: ANN001, ANN202
        if event == "call" and frame.f_code in self.codes:
            self.lines.setdefault(self.current, set()).add((frame.f_code.co_filename, frame.f_lineno))
            return self._local
        return None

    def start(self) -> None:
        import threading

        threading.settrace(self._global)
        sys.settrace(self._global)

    def stop(self) -> None:
        import threading

        sys.settrace(None)
        threading.settrace(None)  # type: ignore[arg-type]

    def rearm(self, nodeid: str) -> None:
        """After test ``nodeid``: when the tracer is no longer installed (CPython removes a trace function that
        raises, e.g. a RecursionError hit inside it by a test of deep recursion: every later test then read as
        covering nothing, and their mutants as survivors without a run), mark the test's coverage unknown and
        put the tracer back."""
        if sys.gettrace() != self._global:  # noqa: PLR1714 - a bound method: equal, not identical
            self.unknown.add(nodeid)
            self.start()

    def covers(self, nodeid: str, filename: str, lo: int, hi: int) -> bool:
        if nodeid in self.unknown:
            return True
        seen = self.lines.get(nodeid, set())
        return any((filename, k) in seen for k in range(lo, hi + 1))


def _run_items(items: list, record: str | None = None, limit: float = 0.0, cover: _Coverage | None = None) -> int:
    """Run the collected test ``items`` in order: 0 when all pass, 1 at the first failure.  With
    ``record`` (the unmutated run), write each test's duration there and stop any test at ``limit``
    CPU seconds (``> 0``): it is recorded as ``"slow"`` and the run goes on.  With ``cover``, record
    the lines of the mutated functions each test executes."""
    from _pytest.runner import runtestprotocol

    code, durations, slow = 0, {}, []
    if cover is not None:
        cover.start()

    def stop(_signum: int, _frame: object) -> None:
        raise _TooSlow(f"more than {limit:g} s CPU")

    if limit > 0:
        signal.signal(signal.SIGPROF, stop)
    for k, item in enumerate(items):
        t0 = time.perf_counter()
        if cover is not None:
            cover.current = item.nodeid
        if limit > 0:
            signal.setitimer(signal.ITIMER_PROF, limit)
        reports = runtestprotocol(item, nextitem=items[k + 1] if k + 1 < len(items) else None, log=False)
        if cover is not None:
            cover.rearm(item.nodeid)
        if limit > 0:
            left = signal.setitimer(signal.ITIMER_PROF, 0)[0]
            if left == 0.0 and any(r.failed and "_TooSlow" in str(r.longrepr) for r in reports):
                slow.append(item.nodeid)
                continue
        durations[item.nodeid] = time.perf_counter() - t0
        if any(r.failed for r in reports):
            code = 1 + min(k, _KILLER_CODES - 1)  # which test failed (the parent tries it first next time)
            break
    if cover is not None:
        cover.stop()
    if limit > 0:
        signal.signal(signal.SIGPROF, signal.SIG_DFL)
    if record:
        Path(record).write_text(json.dumps({"durations": durations, "slow": slow}))
    return code


def _fork(items: list, setup=None, quiet: bool = True) -> int:
    """Fork; the child applies ``setup`` (the mutant), runs the test ``items`` and exits 0 when all
    pass, ``1 + k`` when ``items[k]`` fails, 255 when the mutant cannot even be installed."""
    pid = os.fork()
    if pid:
        with contextlib.suppress(OSError):  # (the child does the same: whichever runs first)
            os.setpgid(pid, pid)
        return pid
    code = 1
    try:
        os.setpgid(0, 0)  # its own process group: a timeout kills the tests' subprocesses with it
        if quiet:
            fd = os.open(os.devnull, os.O_WRONLY)
            os.dup2(fd, 1)
            os.dup2(fd, 2)
        if setup is not None:
            setup()
        code = _run_items(items)
    except BaseException:  # noqa: BLE001 - a mutant that breaks the test machinery is killed
        code = 255
    finally:
        os._exit(code)


def _cpu_seconds(pid: int) -> float:
    """User + system CPU time of a running child (Linux /proc), 0 when unknown."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    except (OSError, IndexError, ValueError):
        return 0.0


def _outcome(status: int) -> tuple[str, int]:
    code = os.waitstatus_to_exitcode(status)
    return ("survived" if code == 0 else "killed"), code


def _kill_group(pid: int) -> None:
    """SIGKILL a mutant's child and every process of its group (the tests' subprocesses), and reap the child."""
    try:
        os.killpg(pid, signal.SIGKILL)
    except OSError:  # not (yet) a group leader: the child alone
        with contextlib.suppress(OSError):
            os.kill(pid, signal.SIGKILL)
    with contextlib.suppress(ChildProcessError):
        os.waitpid(pid, 0)


def _reap(pid: int, started: float, cpu_limit: float, wall_limit: float,
          now: Callable[[], float] = time.monotonic) -> tuple[str, int, str] | None:
    """A running mutant's outcome: ``(status, exit code, which limit)`` when its child has exited or was killed
    for a limit (``"cpu"``: more CPU seconds than ``cpu_limit``; ``"wall"``: running longer than ``wall_limit``
    seconds since ``started``, by ``now``), else None (still running within both limits)."""
    finished, status = os.waitpid(pid, os.WNOHANG)
    if finished:
        return (*_outcome(status), "")
    over = "cpu" if _cpu_seconds(pid) > cpu_limit else "wall" if now() - started > wall_limit else ""
    if not over:
        return None
    _kill_group(pid)
    return "timeout", -9, over


class _Driver:
    """pytest plugin: collect the module's tests once, then run every mutant in a forked child
    (``pytest_runtestloop`` replaced)."""

    def __init__(self, name: str, args: argparse.Namespace) -> None:
        self.name, self.args, self.record = name, args, {}  # type: dict

    def pytest_runtestloop(self, session) -> bool:
        self.record = run_mutants(self.name, list(session.items), self.args)
        return True


def run_module(name: str, args: argparse.Namespace) -> dict:
    import pytest

    driver = _Driver(name, args)
    target = MODULES[name]
    tests = list(args.tests or (LISTED.get(name, ()) if args.listed else target.tests)) \
        or importing_tests(sorted({spec[0] for spec in target.functions}))
    pytest.main(["-qq", "-p", "no:cacheprovider", *tests], plugins=[driver])
    return driver.record


def run_mutants(name: str, items: list, args: argparse.Namespace) -> dict:
    target = MODULES[name]
    modules = {spec[0]: importlib.import_module(spec[0]) for spec in target.functions}
    sources = {mod: Path(inspect.getfile(m)).read_text() for mod, m in modules.items()}
    trees = {mod: ast.parse(text) for mod, text in sources.items()}
    mutants = generate(trees, target.functions, sources)
    print(f"\n== {name}: {len(target.functions)} functions, {len(mutants)} mutants, {len(items)} tests", flush=True)
    if args.list:
        for m, _i, _j in mutants:
            print(f"  {m.id:4d} {m.function}:{m.line} [{m.kind}] {m.before}  ->  {m.after}")
        return {}
    record_file = Path(args.out) / f"{name}.durations.json"
    # the unmutated run, in this process: with the JIT on, its compiled kernels are inherited by every child
    t0, cpu0 = time.monotonic(), resource.getrusage(resource.RUSAGE_SELF)
    cover = None
    if args.select:  # which lines of the mutated functions each test runs: each mutant then runs only those tests
        codes: set = set()
        for spec in target.functions:
            codes |= _codes(_live_function(modules[spec[0]], spec[1]))
        cover = _Coverage(codes)
    code = _run_items(items, record=str(record_file), limit=0.0 if target.tests or args.listed else args.test_limit,
                      cover=cover)
    cpu1 = resource.getrusage(resource.RUSAGE_SELF)
    baseline, baseline_cpu = time.monotonic() - t0, cpu1.ru_utime + cpu1.ru_stime - cpu0.ru_utime - cpu0.ru_stime
    print(f"   baseline: exit {code} in {baseline:.1f} s ({baseline_cpu:.1f} s CPU), JIT "
          f"{'off' if os.environ.get('NUMBA_DISABLE_JIT') == '1' else 'on'}", flush=True)
    if code != 0:
        raise SystemExit(f"{name}: the unmutated tests fail (exit {code})")
    base = json.loads(record_file.read_text())
    durations, slow = base["durations"], base["slow"]
    _SLOW[name] = slow
    if slow:
        print(f"   dropped (unmutated run > {args.test_limit:g} s CPU): {', '.join(slow)}", flush=True)
        items[:] = [item for item in items if item.nodeid not in slow]
        baseline_cpu = sum(durations.values())  # the kept tests' time (wall, an upper bound of their CPU)
    # fastest first (-x stops a killed mutant early), then each killing test moved to the front
    items.sort(key=lambda item: durations.get(item.nodeid, 0.0))
    # a mutant is hung when it has used this much CPU (not wall time: the machine may be loaded)
    timeout = args.timeout or max(10.0, 3.0 * baseline_cpu)
    only = {int(k) for k in args.only.split(",")} if args.only else None
    if args.sample and only is None and args.sample < len(mutants):  # a seeded uniform sample of the mutants
        only = set(random.Random(args.seed).sample([m.id for m, _i, _j in mutants], args.sample))
    fns = {(spec[0], spec[1]): _function_node(trees[spec[0]], spec[1]) for spec in target.functions}
    todo = [(m, i, j) for m, i, j in mutants if only is None or m.id in only]
    files = {name: inspect.getfile(mod) for name, mod in modules.items()}
    running: dict[int, tuple[Mutant, float, list, float, float]] = {}
    done = 0
    while todo or running:
        while todo and len(running) < args.jobs:
            m, i, j = todo.pop(0)
            chosen, limit = list(items), timeout
            if cover is not None:  # only the tests that execute the changed lines (same order)
                chosen = [it for it in items
                          if cover.covers(it.nodeid, files[m.module], min(m.first_line or m.line, m.line), m.end_line)]
                m.tests_run = len(chosen)
                limit = args.timeout or max(10.0, 3.0 * sum(durations.get(it.nodeid, 0.0) for it in chosen))
                if not chosen:  # no test reaches the change: it survives without running anything
                    m.status = "survived"
                    done += 1
                    print("S", end="\n" if done % 60 == 0 else "", flush=True)
                    continue
            new_fn, _ = _mutated(fns[(m.module, m.function)], i, j)

            def setup(new_fn=new_fn, mod=modules[m.module], qualname=m.function) -> None:
                _install(mod, new_fn, qualname)

            wall = args.wall or max(120.0, 10.0 * limit)  # a hang that uses no CPU (a wait, a hung subprocess)
            running[_fork(chosen, setup, quiet=not args.verbose)] = (m, time.monotonic(), chosen, limit, wall)
        time.sleep(0.01)
        for pid, (m, t1, order, limit, wall) in list(running.items()):
            outcome = _reap(pid, t1, limit, wall)
            if outcome is None:
                continue
            m.status, code, m.timeout = outcome
            if 0 < code <= _KILLER_CODES and order[code - 1] in items:  # the killer goes first next time
                items.remove(order[code - 1])
                items.insert(0, order[code - 1])
            del running[pid]
            m.seconds = round(time.monotonic() - t1, 2)
            done += 1
            print({"killed": ".", "survived": "S", "timeout": "T"}[m.status], end="\n" if done % 60 == 0 else "",
                  flush=True)
            if done % 10 == 0:  # the mutants so far (an interrupted run still leaves a record)
                partial = _record(name, target, items, baseline, baseline_cpu, timeout, args, mutants)
                (Path(args.out) / f"{name}.partial.json").write_text(json.dumps(partial))
    print(flush=True)
    return _record(name, target, items, baseline, baseline_cpu, timeout, args, mutants)


def _record(name, target, items, baseline, baseline_cpu, timeout, args, mutants) -> dict:
    return {"module": name, "functions": [".".join(spec[:2]) + (f" [{spec[2]!r}..{spec[3]!r}]" if len(spec) > 2 else "")
                                          for spec in target.functions],
            "tests": [item.nodeid for item in items], "baseline_s": round(baseline, 2),
            "slow": _SLOW.get(name, []), "test_limit_cpu_s": args.test_limit,
            "baseline_cpu_s": round(baseline_cpu, 2), "timeout_cpu_s": timeout, "timeout_wall_s": args.wall or None,
            "jobs": args.jobs, "sample": args.sample, "seed": args.seed,
            "jit": os.environ.get("NUMBA_DISABLE_JIT") != "1", "load": os.getloadavg(),
            "mutants": [asdict(m) for m, _i, _j in mutants]}


def summary(record: dict) -> dict:
    ms = record["mutants"]
    tested = [m for m in ms if m["status"] != "not run"]
    killed = sum(m["status"] == "killed" for m in tested)
    timeout = sum(m["status"] == "timeout" for m in tested)
    wall = sum(m["status"] == "timeout" and m.get("timeout") == "wall" for m in tested)
    survived = [m for m in tested if m["status"] == "survived"]
    score = (killed + timeout) / len(tested) if tested else float("nan")
    return {"generated": len(ms), "tested": len(tested), "killed": killed, "timeout": timeout,
            "timeout_wall": wall, "survived": len(survived), "score": score, "survivors": survived}


def _wilson(k: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """Wilson score interval of a proportion k / n."""
    p = k / n
    centre, half = p + z * z / (2 * n), z * (p * (1 - p) / n + z * z / (4 * n * n)) ** 0.5
    return (centre - half) / (1 + z * z / n), (centre + half) / (1 + z * z / n)


def changed_lines(name: str) -> dict[int, tuple[str, str]]:
    """Mutant id -> (original, mutated) line of the unparsed function (stable across edits elsewhere)."""
    import difflib
    import importlib.util

    target = MODULES[name]
    sources = {}
    for fspec in target.functions:
        spec = importlib.util.find_spec(fspec[0])
        assert spec is not None and spec.origin is not None
        sources[fspec[0]] = Path(spec.origin).read_text()
    trees = {mod: ast.parse(text) for mod, text in sources.items()}
    out = {}
    for m, i, j in generate(trees, target.functions, sources):
        fn = _function_node(trees[m.module], m.function)
        a, b = ast.unparse(fn).splitlines(), ast.unparse(_mutated(fn, i, j)[0]).splitlines()
        diff = [ln for ln in difflib.unified_diff(a, b, lineterm="", n=0)
                if ln[:1] in "+-" and ln[:3] not in ("+++", "---")]
        old = next((ln[1:].strip() for ln in diff if ln.startswith("-")), "")
        new = next((ln[1:].strip() for ln in diff if ln.startswith("+")), "")
        out[m.id] = (old, new)
    return out


def _timeouts(s: dict) -> str:
    """The timeout cell: every mutant killed for a limit (caught), those killed by the wall-clock limit named."""
    return f"{s['timeout']} ({s['timeout_wall']} wall)" if s.get("timeout_wall") else str(s["timeout"])


def _key(m: dict) -> str:
    return f"{m['function']} | {m['change'][1]}"


def report(out: Path, names: list[str]) -> str:
    """Markdown: the per-module table and every survivor with its reason (``REASONS``)."""
    rows = ["| module | functions | tests | generated | tested | killed | timeout | survived (of which equivalent) "
            "| score | score without the equivalent |",
            "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    lines: list[str] = []
    dropped: list[str] = []
    total = dict.fromkeys(("generated", "tested", "killed", "timeout", "timeout_wall", "survived"), 0)
    for name in names:
        path = out / f"{name}.json"
        if not path.exists():
            path = out / f"{name}.partial.json"  # an interrupted run
        if not path.exists():
            rows.append(f"| {name} | not run | | | | | | | | |")
            continue
        record = json.loads(path.read_text())
        if isinstance(record, list):  # an older partial record: the mutants only
            record = {"mutants": record, "functions": MODULES[name].functions, "tests": []}
        lines_of = changed_lines(name)
        files = sorted({t.split("::")[0] for t in record["tests"]})
        dropped.append(f"* **{name}**: {len(record['tests'])} tests of {', '.join(f'`{f}`' for f in files)}"
                       + (f"; dropped as slower than {record.get('test_limit_cpu_s', 0):g} s CPU unmutated: "
                          + ", ".join(f"`{t}`" for t in record["slow"]) if record.get("slow") else ""))
        for m in record["mutants"]:
            m["change"] = lines_of.get(m["id"], ("", ""))
        s = summary(record)
        for k in ("generated", "tested", "killed", "timeout", "timeout_wall", "survived"):
            total[k] += s[k]
        eq = sum(REASONS.get(_key(m), "").startswith("equivalent") for m in s["survivors"])
        score = f"{100 * s['score']:.2f} %"
        if s["tested"] < s["generated"]:  # a sample: Wilson 95 % interval of the module's score
            lo, hi = _wilson(s["killed"] + s["timeout"], s["tested"])
            score += f" (95 % CI {100 * lo:.0f}-{100 * hi:.0f} %)"
        adjusted = (s["killed"] + s["timeout"]) / max(s["tested"] - eq, 1)
        rows.append(f"| {name} | {len(record['functions'])} | {len(record['tests'])} | {s['generated']} | "
                    f"{s['tested']} | {s['killed']} | {_timeouts(s)} | {s['survived']} ({eq}) | {score} | "
                    f"{100 * adjusted:.2f} % |")
        total["equivalent"] = total.get("equivalent", 0) + eq
        for m in s["survivors"]:
            reason = REASONS.get(_key(m), "**not analysed yet**")
            old, new = m["change"]
            lines.append(f"| {name} | `{m['function']}`:{m['line']} | `{old}` → `{new}` | {reason} |")
    score = (total["killed"] + total["timeout"]) / total["tested"] if total["tested"] else float("nan")
    eq = total.get("equivalent", 0)
    adjusted = (total["killed"] + total["timeout"]) / max(total["tested"] - eq, 1)
    rows.append(f"| **all** | | | {total['generated']} | {total['tested']} | {total['killed']} | "
                f"{_timeouts(total)} | {total['survived']} ({eq}) | {100 * score:.2f} % | {100 * adjusted:.2f} % |")
    head = ["| module | function:line | mutant (the changed line) | why it survives |", "| --- | --- | --- | --- |"]
    return ("\n".join(rows) + "\n\nTests run per module:\n\n" + "\n".join(dropped) + "\n\nSurvivors:\n\n"
            + "\n".join(head + lines) + "\n")


BEGIN, END = "<!-- mutate:begin -->", "<!-- mutate:end -->"


def _publish(out: Path, names: list[str], doc: str | None) -> None:
    """Print the summary of ``names``; with ``doc``, replace the block between ``BEGIN`` and ``END`` in that
    file with the summary of every module (the records in ``out``; "not run" where there is none)."""
    print(report(out, names))
    if not doc:
        return
    text = report(out, list(MODULES))
    path = Path(doc)
    old = path.read_text()
    if BEGIN not in old or END not in old:
        raise SystemExit(f"{doc}: no {BEGIN!r} ... {END!r} block to replace")
    head, rest = old.split(BEGIN, 1)
    stamp = time.strftime("%d %b %Y %H:%M UTC", time.gmtime())
    path.write_text(f"{head}{BEGIN}\n\nGenerated by `make mutants` ({stamp}).\n\n{text}\n{END}{rest.split(END, 1)[1]}")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("modules", nargs="*", default=list(MODULES))
    ap.add_argument("--list", action="store_true", help="list the mutants, run nothing")
    ap.add_argument("--report", action="store_true", help="print the markdown summary of the last runs")
    ap.add_argument("--only", help="comma-separated mutant ids")
    ap.add_argument("--timeout", type=float, default=0.0,
                    help="per-mutant CPU seconds (default 3x the baseline's, >= 10)")
    ap.add_argument("--wall", type=float, default=0.0,
                    help="per-mutant wall-clock seconds (default 10x the CPU timeout, >= 120): a mutant whose tests "
                         "wait for ever is killed and counted as a timeout")
    ap.add_argument("--jobs", type=int, default=1, help="mutants run at once")
    ap.add_argument("--test-limit", type=float, default=30.0,
                    help="drop from a target's importing-file selection the tests whose unmutated run uses more "
                         "CPU seconds than this (default 30)")
    ap.add_argument("--tests", nargs="+", help="pytest arguments to run instead of the target's selection (a re-run "
                                                "of survivors against new tests: a kill is a kill, with --only)")
    ap.add_argument("--no-select", dest="select", action="store_false",
                    help="run every mutant against the whole selection (default: only the tests whose unmutated run "
                         "executes the changed lines, recorded by a line tracer)")
    ap.add_argument("--sample", type=int, default=0, help="run a seeded uniform sample of this many mutants")
    ap.add_argument("--seed", type=int, default=23, help="seed of --sample")
    ap.add_argument("--listed", action="store_true",
                    help="the older targets' hand-picked tests (LISTED) instead of every importing test file")
    ap.add_argument("--out", default=str(ROOT / "build" / "mutants"))
    ap.add_argument("--verbose", action="store_true", help="show pytest's output")
    ap.add_argument("--doc", help="also write the summary into this markdown file, between the lines "
                                  f"{BEGIN!r} and {END!r}")
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if args.report:
        _publish(out, args.modules, args.doc)
        return 0
    if len(args.modules) > 1:  # one process per module: each decides whether numba compiles
        rest = [a for a in (argv if argv is not None else sys.argv[1:]) if a not in args.modules and a != "--doc"
                and a != args.doc]
        codes = [subprocess.run([sys.executable, __file__, name, *rest]).returncode for name in args.modules]
        _publish(out, args.modules, args.doc)
        return max(codes)
    if not MODULES[args.modules[0]].jit:
        os.environ["NUMBA_DISABLE_JIT"] = "1"  # the mutated functions are kernels: run them as Python
    worst = 0
    for name in args.modules:
        t0 = time.monotonic()
        record = run_module(name, args)
        if not record:
            continue
        record["wall_s"] = round(time.monotonic() - t0, 1)
        path = out / f"{name}.json"
        if args.only and path.exists():  # a partial re-run: update those mutants in the last record
            old = json.loads(path.read_text())
            fresh = {m["id"]: m for m in record["mutants"] if m["status"] != "not run"}
            old["mutants"] = [fresh.get(m["id"], m) for m in old["mutants"]]
            # the selection the re-run survivors met (a superset of the first pass's: killed stays killed)
            old["tests"], old["slow"] = sorted(set(old["tests"]) | set(record["tests"])), record["slow"]
            old.setdefault("reruns", []).append({"ids": sorted(fresh), "tests": len(record["tests"]),
                                                 "load": record["load"]})
            record = old
        path.write_text(json.dumps(record, indent=1))
        s = summary(record)
        print(f"   {name}: generated {s['generated']}, tested {s['tested']}, killed {s['killed']}, "
              f"timeout {_timeouts(s)}, survived {s['survived']}, score {100 * s['score']:.1f} % "
              f"({record['wall_s']:.0f} s)", flush=True)
        for m in s["survivors"]:
            print(textwrap.indent(f"S {m['id']} {m['function']}:{m['line']} [{m['kind']}] "
                                  f"{m['before']}  ->  {m['after']}", "   "))
        if s["score"] < 0.9:
            worst = 1
    if args.doc:
        _publish(out, args.modules, args.doc)
    return worst


if __name__ == "__main__":
    sys.exit(main())
