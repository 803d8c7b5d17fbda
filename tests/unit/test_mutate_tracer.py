"""``tools/mutate.py``'s line tracer (which tests run each mutant) survives a test that recurses to the limit:
CPython removes a trace function that raises, and a RecursionError raised inside it switched the tracer off for
every later test, whose mutants were then counted as survivors without a run (mutants17: ``test_hostile_readers``'
deeply nested files blinded the durations and qgc-walk runs)."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parents[2] / "tools"))

import mutate  # noqa: E402


def _target(x: float) -> float:
    return x + 1.0


def _deep(n: int) -> int:
    return _deep(n + 1)


def test_a_test_that_hits_the_recursion_limit_does_not_blind_the_tracer():
    outer = sys.gettrace()
    cover = mutate._Coverage(mutate._codes(_target))
    try:
        cover.start()
        cover.current = "deep"
        try:
            _deep(0)
        except RecursionError:
            pass
        cover.rearm("deep")  # the tracer was removed: the test's coverage is unknown, the tracer back
        cover.current = "after"
        _target(1.0)
        cover.rearm("after")  # still installed: nothing to do
    finally:
        cover.stop()
        sys.settrace(outer)
    line = _target.__code__.co_firstlineno + 1
    assert cover.unknown == {"deep"}
    assert cover.covers("deep", "any file", 1, 1)  # run for every mutant
    assert cover.covers("after", __file__, line, line) and not cover.covers("after", __file__, 1, 2)


_FOLDED = '''
def f(x):
    for lo, hi in ((0.0, 1.0),
                   (2.0, 3.0)):
        x = min(max(x, lo), hi)
    return x
'''


def test_a_mutant_inside_a_folded_constant_tuple_runs_the_tests_of_its_statement():
    """mutants20: CPython folds a tuple of constants into one LOAD_CONST carrying the statement's first line, so the
    tracer never sees line 4; its mutants (``2.0 -> 3.0``) were run against no test and counted survivors."""
    import ast

    mutants = [m for m, _i, _j in mutate.generate({"m": ast.parse(_FOLDED)}, (("m", "f"),)) if m.line == 4]
    assert mutants and all(m.first_line == 3 for m in mutants)
    space: dict = {}
    exec(compile(_FOLDED, "folded.py", "exec"), space)  # noqa: S102 - the fixed source above
    outer = sys.gettrace()
    cover = mutate._Coverage(mutate._codes(space["f"]))
    try:
        cover.start()
        cover.current = "t"
        space["f"](5.0)
    finally:
        cover.stop()
        sys.settrace(outer)
    assert not cover.covers("t", "folded.py", 4, 4)  # the folded line itself is never traced
    assert all(cover.covers("t", "folded.py", m.first_line, m.end_line) for m in mutants)
