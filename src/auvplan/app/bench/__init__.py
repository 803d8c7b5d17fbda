"""Sweeps of scenario × planner × guidance × current member × seed on dask.distributed (``auvplan bench``).

* :mod:`~auvplan.app.bench.sweep`: the matrix, its tasks and runs on dask, the Monte Carlo of moving obstacles;
* :mod:`~auvplan.app.bench.members`: current ensemble members and perturbation seeds as axes (issue 39);
* :mod:`~auvplan.app.bench.rows`: the columns, ``rows.csv`` / ``histories.jsonl`` as an interruption left
  them, and the summary per cell.
"""

from .rows import COLUMNS, KEY, TIMING, Row, read_histories, read_rows, summarise
from .sweep import SweepSpec, _todo, fast_movers, perturb_moving, run_chunk, sweep  # noqa: F401 (_todo: tests)

__all__ = ["SweepSpec", "COLUMNS", "KEY", "TIMING", "Row", "perturb_moving", "fast_movers", "run_chunk", "sweep",
           "summarise", "read_rows", "read_histories"]
