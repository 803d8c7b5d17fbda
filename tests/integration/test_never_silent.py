"""Issue 56: no phase of a command is silent for more than ~2 s.  The suite's version of ``make never-silent``
(a 31 h mission, tests/heavy/test_never_silent_long.py): a job of the command line's shape run in a fresh
process — its reporter, a stage that sleeps, one that computes in Python holding the GIL, a flight whose
expected duration is overrun by half (the bar used to stop at 100 %), then the result — every stderr line
timed inside the job's process, less the time the machine did not run it (tests/timed_stderr.py; ``-q`` and
``--json`` leaving stderr empty: tests/integration/test_cli.py, test_deploy.py)."""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

from helpers import stderr_gaps
from timed_stderr import silent_spans

JOB = r'''
import sys, time
from timed_stderr import record
record(sys.argv[3])  # every stderr write timed in this process, and the time this process could not run

from auvplan.cli import output

quiet, phase = sys.argv[1] == "quiet", float(sys.argv[2])
print("job", file=sys.stderr, flush=True)  # the interpreter has started: the oracle's clock starts here
make = output.reporter(quiet)         # the command's clock from its start
from auvplan.planners import PlannerSpec  # reading the scenario: imports

time.sleep(phase)                     # ... and waiting on a file
bar = make(PlannerSpec(name="grid"), "scene")
bar.stage("writing results")
t0 = time.monotonic()
while time.monotonic() - t0 < phase:  # a stage computing in Python (holding the GIL between switches)
    sum(i * i for i in range(1000))
for k in range(100):                  # a flight 50 % longer than first expected
    bar.flight(100.0 * k, 6600.0 if k < 10 else 100.0 * k * 1.5)
    time.sleep(0.01)
bar.close()
time.sleep(phase)                     # after the flight: energy, checks
output.emit({"ok": True}, False, "done")
'''

BOUND_S = 2.0


def test_every_phase_shows_within_two_seconds(tmp_path):
    """Timed in the job's own process, less the time it could not run: a loaded machine (CI: the suite beside
    mypy, the kernels' warm-up and other jobs) delays every thread of it, the reporter's too, by seconds (3.1 s
    seen before the first line at a load of 8.5, the reporter's thread then silent because it was not run) — a
    stall the code cannot shorten.  A reporter that stays silent through a 2.2 s phase fails on a machine that
    runs it."""
    timing = tmp_path / "timing.json"
    code, gaps = stderr_gaps([sys.executable, "-c", JOB, "loud", "2.2", str(timing)],
                             env={**os.environ, "PYTHONPATH": os.pathsep.join([str(Path(__file__).parents[1]),
                                                                                *sys.path])})
    assert code == 0
    assert gaps[0][1] == "job"  # from here on (the interpreter's own start is not the job's)
    silences = silent_spans(json.loads(timing.read_text()), after="job")
    assert max(s for s, _, _ in silences) <= BOUND_S, sorted(silences, reverse=True)[:3]
    text = " ".join(line for _, line in gaps)
    assert "reading the scenario and its data" in text and "writing results" in text
    bars = [line for _, line in gaps if line.startswith("flight on scene")]
    done, total = (int(v) for v in bars[-1].split("|")[2].split()[0].split("/"))
    assert total > 6600 and abs(total - 1.5 * done) <= 150  # the estimate followed the flight past its first 6 600 s
