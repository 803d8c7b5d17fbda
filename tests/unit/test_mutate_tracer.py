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
