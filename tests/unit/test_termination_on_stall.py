"""``Termination.on_stall``: asked when the stall count is reached; True stops the run, False resets the count."""

from __future__ import annotations

import numpy as np

from auvplan.optim import IABC, Problem, Termination, minimize


def _flat(X: np.ndarray) -> np.ndarray:
    """The same value everywhere: the first iteration's best is never improved."""
    return np.ones(X.shape[0])


def _run(on_stall, stall=3, iterations=12):  # type: ignore[no-untyped-def]
    lo, hi = np.zeros(2), np.ones(2)
    opt = IABC(lo, hi, 6, rng=np.random.default_rng(0))
    return minimize(Problem(_flat, lo, hi), opt, Termination(max_iterations=iterations, stall_iterations=stall,
                                                            on_stall=on_stall))


def test_a_stall_that_goes_on_resets_the_count_and_the_run_ends_at_its_cap() -> None:
    asked: list[tuple[int, float]] = []
    res = _run(lambda best: asked.append((len(asked), best)) is not None)  # always False
    # iteration 1 improves (inf -> 1), iterations 2-4 stall: asked after 4, 7 and 10; 12 is the cap
    assert res.reason == "max_iterations" and res.iterations == 12
    assert [b for _, b in asked] == [1.0, 1.0, 1.0]


def test_a_stall_that_says_stop_stops_the_run_there() -> None:
    calls: list[float] = []

    def second(best: float) -> bool:
        calls.append(best)
        return len(calls) == 2

    res = _run(second)
    assert res.reason == "stall" and res.iterations == 7 and len(calls) == 2
    assert len(res.history) == 7


def test_without_on_stall_the_stall_stops_the_run() -> None:
    res = _run(None)
    assert res.reason == "stall" and res.iterations == 4
