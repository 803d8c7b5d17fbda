"""Count the hostile-input cases of round 3 (issue 48) by class and how many were mishandled.

Runs ``tests/integration/test_hostile_round3.py`` and ``tests/integration/test_hostile_serve3.py``
(junit XML), puts each test
case in its class by the test function's name, counts the inputs of the few tests that assert several
(the five scenario files, the two streamed bodies, busy and superseded, the three dropped clients, the
two ``validate`` files) and writes the table to ``docs/figures/hostile-round3.md`` with ``--figure``
(quoted in docs/hostile-input.md).  A failed case is a mishandled one.

    python tools/hostile_cases.py [--figure]
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FILES = ("tests/integration/test_hostile_round3.py", "tests/integration/test_hostile_serve3.py")

CLASSES = [  # (class, example, the test functions' names)
    ("serve: edited and typed positions", "insert at x = 1e9, `\"inf\"`, `[1, 2]`, `true`; depth 1e12 (a depth "
     "above the surface: accepted, shown as a violation)",
     ("test_an_edit_outside_the_area", "test_a_typed_depth", "test_an_edit_inside_the_area")),
    ("serve: waypoint indices and edit ops", "index −1, 2⁷⁰, `\"0\"`, 1.5, `null`; op `\"teleport\"`",
     ("test_a_bad_waypoint_index", "test_an_unknown_edit")),
    ("serve: scenario keys through the page", "`[endurance] ds_m = 1e-9`, `population = 10⁹`, `[terrain] file`",
     ("test_a_bad_setting",)),
    ("serve: survey areas", "a polygon 10⁹ m wide, 2 points, a bow tie, `1e400`, `\"square\"`",
     ("test_a_bad_survey_area",)),
    ("serve: request bodies and Host", "300 MB declared, 64 MiB chunked, nested 10⁵ deep, `Host: testserver`",
     ("test_a_bad_request_body", "test_a_body_over_the_limit", "test_the_production_host_list")),
    ("serve: files a scenario names", "currents by `../`, absolute, a tide file, a member file, a link out",
     ("test_scenario_files_outside",)),
    ("serve: long work and dropped clients", "a second long request (503 busy), an edit during a re-plan "
     "(409 superseded), 3 drops mid-body", ("test_long_work_runs_aside", "test_a_client_dropping")),
    ("estimator: endurance, members, survey", "`ds_m = 1e-9`, a 1.4·10⁹ m leg, 21 × 1 000 members, `iterations = 10⁹`, "
     "`station_m = 1e-6`",
     ("test_the_energy", "test_ensemble_members", "test_survey_sizes", "test_endurance_ds_m", "test_a_long_route",
      "test_perturbation_members", "test_survey_settings", "test_the_builtin_survey", "test_a_plan_of_hours")),
    ("mission files", "2-D KML/GeoJSON, Point, flat list, polygon, `tail_first_legs: [1e400]`, a 10⁹ m leg",
     ("test_odd_geojson", "test_geojson_without", "test_a_3d_kml", "test_odd_kml", "test_odd_tail",
      "test_mission_check_of_a_2d")),
    ("command line", "`--port 99999`, `validate` of what `plan` refuses",
     ("test_a_bad_port", "test_validate_exits_2")),
    ("results folders", "`run` then `survey`, `plan`, `bench`; `--force`",
     ("test_a_folder_written_by_another", "test_force_removes")),
]

INPUTS = {"test_scenario_files_outside": 5, "test_a_body_over_the_limit": 2, "test_long_work_runs_aside": 2,
          "test_a_client_dropping": 3, "test_validate_exits_2": 2,
          "test_mission_check_of_a_2d": 2}
"""Tests asserting the contract on several inputs: how many."""


def classify(name: str) -> str:
    """The class of a test case by its function's name (a case of no class is an error)."""
    for label, _, prefixes in CLASSES:
        if name.startswith(prefixes):
            return label
    raise ValueError(f"{name}: in no class")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--figure", action="store_true", help="write docs/figures/hostile-round3.md")
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        xml = Path(tmp) / "r.xml"
        subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:warnings", "-p", "no:cacheprovider",
                        f"--junitxml={xml}", *FILES], cwd=ROOT, check=False, capture_output=True)
        cases, bad = Counter(), Counter()
        for tc in ET.parse(xml).getroot().iter("testcase"):
            name = tc.get("name", "").split("[")[0]
            label = classify(name)
            n = next((k for prefix, k in INPUTS.items() if name.startswith(prefix)), 1)
            cases[label] += n
            if tc.find("failure") is not None or tc.find("error") is not None:
                bad[label] += n
    lines = ["| class | example | cases | mishandled |", "| --- | --- | ---: | ---: |"]
    lines += [f"| {label} | {example} | {cases[label]} | {bad[label]} |" for label, example, _ in CLASSES]
    lines.append(f"| **total** | | **{sum(cases.values())}** | **{sum(bad.values())}** |")
    files = ", ".join(f"`{f}`" for f in FILES)
    text = "\n".join(lines) + f"\n\n`python tools/hostile_cases.py --figure`: {files}."
    print(text)
    if args.figure:
        (ROOT / "docs" / "figures" / "hostile-round3.md").write_text(text + "\n", encoding="utf-8")
    return 1 if sum(bad.values()) else 0


if __name__ == "__main__":
    sys.exit(main())
