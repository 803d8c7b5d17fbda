"""mutants20: ``run.npz``'s member checks (``io/results/readback.py``; docs/mutants.md section 7).  Oracle: the
time series' contract — finite and non-decreasing (a repeated sample, as at an event, is a time series; one NaN or
one step back is not) — and the positions' ``(N, 3)`` finite rows, on arrays built by hand."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.io.results import readback


def _arrays(t):
    t = np.asarray(t, dtype=float)
    arr = {"route": np.zeros((2, 3)), "sim_t": t, "sim_position": np.zeros((t.size, 3))}
    arr |= {f"sim_{k}": np.zeros(t.size) for k in readback.SIM_ARRAYS[2:]}
    return arr


def test_a_repeated_time_sample_is_a_time_series():
    readback._check_arrays(_arrays([0.0, 0.1, 0.1, 0.2]), flown=True)


@pytest.mark.parametrize("t", [[0.0, np.nan, 0.2, 0.3], [0.0, 0.2, 0.1, 0.3], [0.0, 0.1, np.inf]])
def test_one_nan_or_one_step_back_is_refused(t):
    with pytest.raises(readback._ArrayFault, match="is not a finite, non-decreasing time series"):
        readback._check_arrays(_arrays(t), flown=True)


def test_a_position_row_that_is_not_finite_is_named():
    arr = _arrays([0.0, 0.1, 0.2])
    arr["sim_position"][1, 2] = np.nan
    with pytest.raises(readback._ArrayFault, match=r"member 'sim_position' holds a value that is not finite \(row 1\)"):
        readback._check_arrays(arr, flown=True)
    arr = _arrays([0.0, 0.1, 0.2])
    arr["route"] = np.zeros((2, 2))
    with pytest.raises(readback._ArrayFault, match=r"member 'route' has the shape \(2, 2\), not \(N, 3\)"):
        readback._check_arrays(arr, flown=False)


def _rows(path, seeds, newline="\r\n", tail=""):
    from auvplan.app.bench.rows import COLUMNS

    def line(seed):
        values = {k: "" for k in COLUMNS} | {"scenario": "track-single", "planner": "route", "guidance": "hybrid",
                                             "seed": seed, "status": "EXACT", "wall_s": "0.5"}
        return ",".join(values[k] for k in COLUMNS) + newline

    path.write_text(",".join(COLUMNS) + newline + "".join(line(s) for s in seeds) + tail, encoding="utf-8",
                    newline="")
    return path


def test_a_bad_row_is_skipped_not_the_end_of_the_file(tmp_path):
    """The rows after a dropped one are read (a seed 'x' first, then 0 and 1)."""
    from auvplan.app.bench.rows import read_rows

    assert [r["seed"] for r in read_rows(_rows(tmp_path / "r.csv", ["x", "0", "1"]))] == ["0", "1"]


def test_complete_lines_are_read_whatever_their_ending_and_a_partial_one_is_not(tmp_path):
    """LF-only lines keep their last field; a line cut by a kill (no newline) is left for the sweep to redo; a file
    cut inside its header (no newline yet) holds no row and is no foreign file."""
    from auvplan.app.bench.rows import COLUMNS, read_rows

    rows = read_rows(_rows(tmp_path / "lf.csv", ["0", "1"], newline="\n"))
    assert [r["seed"] for r in rows] == ["0", "1"] and all(None not in r.values() for r in rows)
    cut = read_rows(_rows(tmp_path / "cut.csv", ["0"], tail="track-single,route,hy"))
    assert [r["seed"] for r in cut] == ["0"]
    (tmp_path / "head.csv").write_text(",".join(COLUMNS)[:7], encoding="utf-8")
    assert read_rows(tmp_path / "head.csv") == []
