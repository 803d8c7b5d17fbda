"""tools/identity_dump.py leaves out exactly the clock fields (wall and CPU times differ run to run), so two
dumps of the same commit are equal and any difference left is a result's."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).parents[2]


def _tool():
    spec = importlib.util.spec_from_file_location("identity_dump", ROOT / "tools" / "identity_dump.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["identity_dump"] = module
    spec.loader.exec_module(module)
    return module


def test_clock_fields_are_left_out_by_name_and_results_kept():
    tool = _tool()
    record = {"plan": {"cost": 2.5, "work": {"seeding_cpu_s": 0.3, "polish_cpu_s": 0.1, "evaluations": 40},
                       "wall_time_s": 1.2},
              "sim": {"duration_s": 300.0, "min_altitude_m": 9.5, "decision_time_s": [0.1, 0.2]},
              "setup": {"build_s": 0.7, "cell": 500.0}}
    out: dict[str, np.ndarray] = {}
    tool._flatten(record, "s/run", out)
    assert sorted(out) == ["s/run/plan/cost", "s/run/plan/work/evaluations", "s/run/setup/cell",
                           "s/run/sim/duration_s", "s/run/sim/min_altitude_m"]
    assert tool.is_clock("a/b/search_cpu_s") and not tool.is_clock("a/cpu_s/cost")  # only the last part counts
