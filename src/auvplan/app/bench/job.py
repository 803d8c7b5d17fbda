"""``bench`` as a job: the sweep of scenarios × planners × guidance × seeds on dask (:mod:`auvplan.app.bench`), its
summary table (``summary.csv``, ``summary.md``), figures and HTML report."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ...io.files.safeio import atomic_write, prepare_out, save_figure

__all__ = ["BENCH_NAMES", "bench"]

BENCH_NAMES = ("summary.csv", "summary.md", "bench.html", "bench.png")
"""Files of ``bench --out`` besides rows.csv and histories.jsonl (which ``--resume`` appends to)."""


def bench(spec: Any, out: str | Path, force: bool = False, workers: int = 2, scheduler: str | None = None,
          resume: bool = False, retries: int = 1) -> tuple[Path, list[dict[str, Any]], str]:
    """Run a benchmark sweep and write its summary, figures and report.

    Parameters
    ----------
    spec : SweepSpec
        The sweep (:class:`auvplan.app.bench.sweep.SweepSpec`).
    out : str or pathlib.Path
        The folder of ``rows.csv``, ``histories.jsonl`` and the summary.
    force : bool
        Replace the summary files.
    workers : int
        Local worker processes.
    scheduler : str, optional
        Address of an existing dask scheduler.
    resume : bool
        Complete an interrupted sweep in ``out``.
    retries : int
        Runs again of a chunk of runs that fails (:class:`auvplan.runtime.parallel.Runner`).

    Returns
    -------
    out : pathlib.Path
        The folder.
    rows : list of dict
        The runs.
    text : str
        The summary table (Markdown).
    """
    from ...viz.plots import bench_figures
    from ...viz.report import build_bench_report
    from ..bench import read_histories, summarise, sweep

    folder = prepare_out(out, ("rows.csv", "histories.jsonl", *BENCH_NAMES), force=force,
                          job="bench")  # no link in the way
    rows = sweep(spec, folder, workers=workers, scheduler=scheduler, resume=resume, retries=retries)
    table = summarise(rows)
    cols = list(table[0]) if table else []
    atomic_write(folder / "summary.csv", "".join(",".join(str(v) for v in r) + "\n"
                                                 for r in [cols] + [[r[c] for c in cols] for r in table]))
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    lines += ["| " + " | ".join(f"{r[c]:.6g}" if isinstance(r[c], float) else str(r[c]) for c in cols) + " |"
              for r in table]
    text = "\n".join(lines)
    atomic_write(folder / "summary.md", f"# auvplan bench: {len(rows)} runs\n\n{text}\n")
    bench_figures(rows, folder, save=save_figure)
    page = build_bench_report(rows, table, read_histories(folder / "histories.jsonl"))
    atomic_write(folder / "bench.html", page)
    return folder, rows, text
