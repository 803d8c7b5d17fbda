"""Issue 56: a long mission is never silent.  ``auvplan run marcus-wake --out`` (a 140 km route at 1 m/s: a
~31 h flight, then the results, the report and the exports of its track) in a fresh process, every stderr line
timed: no gap between two lines (or from the start, or to the exit) over 2 s.  Minutes of CPU: ``make
never-silent`` (the suite runs the small version, tests/integration/test_never_silent.py)."""

from __future__ import annotations

import os
import sys

from helpers import stderr_gaps

SCENARIO = os.environ.get("AUVPLAN_SILENT_SCENARIO", "marcus-wake")
BOUND_S = 2.0


def test_a_long_mission_has_no_silent_phase(tmp_path):
    code, gaps = stderr_gaps([sys.executable, "-m", "auvplan", "run", SCENARIO, "--out", str(tmp_path / "r")])
    assert code == 0
    flight = [line for _, line in gaps if line.startswith(f"flight on {SCENARIO}")]
    total = int(flight[-1].split("/")[1].split()[0])  # the bar's last estimate of the flight (s)
    worst = sorted(gaps, reverse=True)[:5]
    longest = "; ".join(f"{g:.2f} s before {line[:60]!r}" for g, line in worst)
    print(f"\n{SCENARIO}: flight ~{total / 3600:.1f} h simulated, {len(gaps)} stderr lines in "
          f"{sum(g for g, _ in gaps):.0f} s; longest gaps: {longest}")
    assert total >= 15 * 3600
    assert worst[0][0] <= BOUND_S, worst
