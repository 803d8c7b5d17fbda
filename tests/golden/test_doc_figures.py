"""The docs cannot drift (issue 40): quoted figures equal their measured files, the README stays a front
page whose commands are the ones CI and make run, its links resolve and its lat/lon example runs as written.
Text comparisons only: nothing here re-runs a benchmark."""

from __future__ import annotations

import importlib.util
import re
import sys
from pathlib import Path

import pytest

from auvplan.io.scenario import loader as sc

ROOT = Path(__file__).parents[2]
README = ROOT / "README.md"


def _tool():
    spec = importlib.util.spec_from_file_location("docs_figures", ROOT / "tools" / "docs_figures.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["docs_figures"] = module
    spec.loader.exec_module(module)
    return module


def test_every_documented_figure_matches_its_source_file():
    tool = _tool()
    quoted = [name for doc in tool.doc_files() if doc.exists() for name, _ in tool.blocks(doc.read_text())]
    assert {"demo-cost", "demo-flight", "missions", "gauntlet-predictive", "doc001-tracking", "formation-chagos",
            "sim-hour", "shelf-survey", "track-200km", "oracle-mutants", "ensemble-replan", "shelf-survey-table",
            "endurance-prediction", "ensemble-table", "terrain-follow", "lofoten-robust"} <= set(quoted)
    assert tool.problems() == []


def _tree(tmp_path: Path, figure: str, quoted: str) -> Path:
    (tmp_path / "docs" / "figures").mkdir(parents=True)
    (tmp_path / "docs" / "figures" / "wall.md").write_text(figure)
    (tmp_path / "README.md").write_text(f"The demo takes <!-- figure: wall -->{quoted}<!-- /figure --> to run.\n")
    return tmp_path


def test_a_stale_missing_or_orphan_figure_is_reported_and_sync_repairs_it(tmp_path):
    tool = _tool()
    root = _tree(tmp_path, "7 s wall\n", "4.0 s wall")
    assert tool.problems(root) == ["README.md: figure 'wall' differs from docs/figures/wall.md"]
    assert tool.sync(root) == [root / "README.md"]
    assert (root / "README.md").read_text() == "The demo takes <!-- figure: wall -->7 s wall<!-- /figure --> to run.\n"
    assert tool.problems(root) == [] and tool.sync(root) == []
    (root / "docs" / "figures" / "orphan.md").write_text("1\n")
    (root / "docs" / "guide.md").write_text("<!-- figure: gone -->\n| a |\n<!-- /figure -->\n")
    assert tool.problems(root) == ["docs/guide.md: figure 'gone' has no file docs/figures/gone.md",
                                   "docs/figures/orphan.md is quoted nowhere"]


def test_a_table_figure_keeps_its_own_lines(tmp_path):
    tool = _tool()
    root = _tree(tmp_path, "| a | b |\n| --- | --- |\n| 1 | 2 |\n", "x")
    (root / "README.md").write_text("before\n<!-- figure: wall -->\nold\n<!-- /figure -->\nafter\n")
    tool.sync(root)
    assert (root / "README.md").read_text() == \
        "before\n<!-- figure: wall -->\n| a | b |\n| --- | --- |\n| 1 | 2 |\n<!-- /figure -->\nafter\n"


def test_readme_is_a_front_page_with_the_two_commands_ci_runs():
    text = README.read_text()
    assert len(text.splitlines()) < 200
    first = re.search(r"```sh\n(.*?)```", text, re.S).group(1)
    assert first.startswith("make demo") and "\nmake test" in first
    assert re.search(r"^make test$", (ROOT / ".ci" / "run").read_text(), re.M)
    makefile = (ROOT / "Makefile").read_text()
    assert re.search(r"^demo: ", makefile, re.M) and re.search(r"^test: ", makefile, re.M)
    for job in ("plan", "run", "survey", "--depart-between", "formation", "mission check", "serve"):
        assert f"auvplan {job}" in text or job in text, job


@pytest.mark.parametrize("doc", ["README.md", "docs/README.md"])
def test_relative_links_resolve(doc):
    path = ROOT / doc
    links = re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", path.read_text())
    local = [link for link in links if "://" not in link]
    assert local
    missing = [link for link in local if not (path.parent / link).exists()]
    assert not missing, missing


def test_readme_lat_lon_example_builds_as_written(tmp_path):
    """The front page's own-data example validates (the World is built: origin (midway) and bounds derived
    from the points, the start placed 100 m above the seabed)."""
    block = next(b for b in re.findall(r"```toml\n(.*?)```", README.read_text(), re.S) if "lat =" in b)
    scenario = sc.loads(block, "README.md")
    assert (scenario.origin.lat, scenario.origin.lon) == pytest.approx((15.2, 159.1))  # midway, from the points
    world, mission = sc.build(scenario)
    start, b = mission.start, world.bounds
    for p in (start, mission.goal):  # the derived bounds hold both points with a margin
        assert b.xmin < p[0] < b.xmax and b.ymin < p[1] < b.ymax
    assert start[2] - world.terrain.elevation(start[0], start[1]) == pytest.approx(100.0, abs=0.5)
    assert mission.goal[2] == pytest.approx(-1500.0)


def test_guide_toml_sketches_parse():
    blocks = re.findall(r"```toml\n(.*?)```", (ROOT / "docs" / "guide.md").read_text(), re.S)
    full = [b for b in blocks if "[mission]" in b and "goal" in b]
    assert len(full) >= 2
    for block in full:
        assert sc.loads(block, "docs/guide.md").mission.goal


# Number-bearing table rows of docs/performance.md that are still typed by hand (not yet between figure
# markers).  A new hand-typed row fails test_performance_table_rows_are_figures_or_allowed; an entry whose row
# has gone (converted to a figure, or removed) fails too, so this list only shrinks.  Each names its owner.
HAND_TYPED_SECTIONS = {
    "On the hard scenarios": "conv (#35.1: benchmarks/hard.py, iabc_ablation.py re-measured this wave)",
}
HAND_TYPED_ROWS = {  # first cell of the summary table's row -> owner
    "one IABC plan on marcus-wake": "conv (#35.1 swarm CPU)",
    "cost evaluations per CPU second": "conv (#35.1 swarm CPU)",
    "current at one population's midpoints": "unowned: benchmarks/currents.py, not yet a figure",
    "grid reference on marcus-wake": "lattice (#35.2)",
    "OMPL Informed RRT*": "unowned: benchmarks/ompl_peer.py needs OMPL in a separate venv",
    "dynamic-terrain Monte Carlo": "avoid (#36.4 Monte Carlo)",
    "the same 500 seeds with document 004's APF": "avoid (#36.4; measured with wave 2's code)",
    "predictive vs APF decision step": "avoid (#36.4)",
    "document 004 APF decision step": "avoid (#36.4)",
    "juan-de-fuca-tides, one timed plan": "timeopt",
    "juan-de-fuca-tides, departures every 30 min": "timeopt",
    "same 2D slice": "timeopt (peer hj_reachability in a separate venv)",
    "flow, 500 random starts per scene": "flowbody (#36.1)",
    "bodies round the ellipsoids": "flowbody (#36.1)",
}


def _measured_rows(text: str) -> list[tuple[str, str, str]]:
    """``(section, first cell, row)`` of every table row outside figure blocks with a digit past its first
    cell, once inline code (commands, names) is set aside: the rows whose numbers were typed by hand."""
    tool = _tool()
    section, out = "", []
    for line in tool.BLOCK.sub("", text).splitlines():
        if line.startswith("## "):
            section = line[3:].strip()
        if not line.startswith("|"):
            continue
        cells = [c.strip() for c in re.sub(r"`[^`]*`", "", line).strip().strip("|").split("|")]
        if any(re.search(r"\d", c) for c in cells[1:]):
            out.append((section, cells[0], line))
    return out


def _hand_typed(text: str) -> tuple[list[str], set[str], set[str]]:
    rows, sections, labels = [], set(), set()
    for section, first, line in _measured_rows(text):
        label = next((k for k in HAND_TYPED_ROWS if first.startswith(k)), None)
        if section in HAND_TYPED_SECTIONS:
            sections.add(section)
        elif label is not None:
            labels.add(label)
        else:
            rows.append(line[:120])
    return rows, sections, labels


def test_performance_table_rows_are_figures_or_allowed():
    rows, sections, labels = _hand_typed((ROOT / "docs" / "performance.md").read_text())
    assert rows == [], "hand-typed numbers: measure them into docs/figures/ and quote them with a marker"
    assert sections == set(HAND_TYPED_SECTIONS), "an allowed section has no hand-typed row left: drop it"
    assert labels == set(HAND_TYPED_ROWS), "an allowed row is gone or converted: drop it from the list"


# The other docs/*.md under the same guard: a number-bearing table row outside a figure block fails unless
# its section is listed here, with its owner, and why it is still typed by hand.  Reference tables (parameter
# defaults, definitions, oracles worked by hand) are listed as such; measured ones name who owns turning them
# into figures.  An entry whose section has no such row left fails too, so the list only shrinks.
NOT_MEASURED = "docs: reference table (definitions, defaults, oracles by hand), no measured number"
HAND_TYPED_DOC_SECTIONS = {
    ("docs/conventions.md", "Words with one meaning each"): NOT_MEASURED,
    ("docs/data.md", "The seabed is never deeper than its data"):
        "unowned: the conservative-seabed measurements, no figure tool yet",
    ("docs/endurance.md", "The model"): NOT_MEASURED,
    ("docs/energy_readings.md", ""): "unowned: benchmarks of the energy readings, not yet a figure",
    ("docs/ensembles.md", "Several current fields: `[currents] members`"): NOT_MEASURED,
    ("docs/guide.md", "Scenarios"): NOT_MEASURED,
    ("docs/guide.md", "Tidal currents and time-optimal planning"): "unowned: timeopt's measured closure, no figure",
    ("docs/hostile-input.md", "Resource estimates before allocating"): NOT_MEASURED,
    ("docs/methods.md", "The documents"): NOT_MEASURED,
    ("docs/missions.md", "Hand it to the vehicle"): NOT_MEASURED,  # format fields and codes (issue 51)
    ("docs/missions.md", "Vehicle presets"): "docs: manufacturers' published figures, sources in the table (#51)",
    ("docs/methods.md", "Where each method lives"): NOT_MEASURED,
    ("docs/methods.md", "1. Potential-flow streamline planning (document 000)"): NOT_MEASURED,
    ("docs/mutants.md", "1. The catalogue (28 of 28 killed)"): NOT_MEASURED,
    ("docs/mutants.md", "2. Mutation testing of the safety-relevant functions"):
        "docs: `make mutants` (hours of CPU), not re-run in wave 6",
    ("docs/mutants.md", "3. Issue 49: the bugs that survived the wave's suite, and the new modules"):
        "docs: tools/oracle_mutants.py edges-* and tools/mutate.py runs (hours of CPU), issue 49",
    ("docs/mutants.md", "4. Wave 12's safety code (6 Dec 2026, evening)"):
        "docs: tools/mutate.py runs of wave 12's safety code (about 40 min of a heavy slot), wave 13",
    ("docs/mutants.md", "5. Wave 13's new code (6 Dec 2026, night)"):
        "docs: tools/mutate.py runs of wave 13's new code (18 min of a heavy slot), mutants17",
    ("docs/mutants.md", "6. This session's new code (7 Dec 2026, after midnight)"):
        "docs: tools/mutate.py runs of the session's new code (about 10 min of a heavy slot), mutants19",
    ("docs/mutants.md", "7. The session's hostile20 and fix20 code (7 Dec 2026, ~02:30)"):
        "docs: tools/mutate.py runs of the session's hostile20/fix20 code (about 25 min of heavy slots), mutants20",
    ("docs/mutants.md", "8. Never mutated before: cached kernels, lazy names, the --out folder (7 Dec 2026, ~04:30)"):
        "docs: tools/mutate.py runs of cacheload, lazy, the --out folder and zones-near (8.5 min of heavy slots), "
        "mutants21",
    ("docs/mutants.md", "9. The last two waves' code no run had seen: the exact EDT, the waits in mission files, a "
                        "`.plan` as WPNav flies it (7 Dec 2026, ~07:00, audit-w17)"):
        "docs: tools/mutate.py runs of edt, dwell and wpnav-speeds (heavy slots), audit-w17",
    ("docs/mutants.md", "10. The last wave's new code: the antimeridian cut, the ahead-of-time binding, each kernel's "
                        "own callees, the fence storage, a glider's yos, the launch, the hazards under the error "
                        "(7 Dec 2026, ~09:15, mutants-w18)"):
        "docs: tools/mutate.py runs of round 10's seven targets (35 min of heavy slots), mutants-w18",
    ("docs/missions.md", "Every leg as a helm flies it"):
        "issue 49: measured on 6 Dec 2026 (fitted_route, exports, mission check, closed-loop pieces), not yet a "
        "docs_figures measurement; tests/integration/test_mission_legs.py holds the limits, the band and the flight",
    ("docs/reference.md", "Resolution study (`benchmarks/grid.py`)"): "unowned: benchmarks/grid.py (heavy), no figure",
    ("docs/reference.md", "Gap study (`benchmarks/gap.py`)"): "unowned: benchmarks/gap.py (heavy), no figure",
    ("docs/reliability.md", "Bad input"): NOT_MEASURED,
    ("docs/safety.md", "`auvplan mission check`"): NOT_MEASURED,
    ("docs/safety.md", "The planted bugs the suite must catch"): NOT_MEASURED,
}
UNGUARDED_DOCS = {  # generated, or owned by another helper this wave (guard them once merged)
    "docs/architecture.md": "generated by tools/architecture.py",
    "docs/scenario-reference.md": "generated by tools/scenario_reference.py",
    "docs/performance.md": "its own test above",
    "docs/bench_hard.md": "conv (wave 6)", "docs/lattice.md": "lattice (wave 6)", "docs/flow.md": "flowturn (wave 6)",
    "docs/timeopt.md": "tailfirst (wave 6)", "docs/serve.md": "serveplus (wave 6)",
}


def _guarded_docs() -> list[str]:
    return [str(p.relative_to(ROOT)) for p in sorted((ROOT / "docs").glob("*.md"))
            if str(p.relative_to(ROOT)) not in UNGUARDED_DOCS]


def _unlisted_rows(doc: str, text: str) -> tuple[list[str], set[tuple[str, str]]]:
    """Rows of ``doc`` whose section is not on the list, and the listed sections that still hold rows."""
    rows, seen = [], set()
    for section, _, line in _measured_rows(text):
        if (doc, section) in HAND_TYPED_DOC_SECTIONS:
            seen.add((doc, section))
        else:
            rows.append(f"{doc} ({section or 'no section'}): {line[:100]}")
    return rows, seen


def test_measured_numbers_in_the_other_docs_are_figures_or_allowed():
    rows, seen = [], set()
    for doc in _guarded_docs():
        r, s = _unlisted_rows(doc, (ROOT / doc).read_text())
        rows += r
        seen |= s
    assert rows == [], "hand-typed numbers: measure them into docs/figures/ and quote them with a marker"
    assert set(HAND_TYPED_DOC_SECTIONS) - seen == set(), "an allowed section has no hand-typed row left: drop it"


def test_a_planted_hand_typed_row_in_a_guarded_doc_is_caught():
    """The survey table as it was typed before it became a figure fails; the same table quoted as a figure passes."""
    assert "docs/survey.md" in _guarded_docs() and "docs/ensembles.md" in _guarded_docs()
    typed = "## The built-in survey\n| | auvplan | lawnmower |\n| --- | --- | --- |\n| lines | **18** | 22 |\n"
    rows, _ = _unlisted_rows("docs/survey.md", typed)
    assert rows == ["docs/survey.md (The built-in survey): | lines | **18** | 22 |"]
    quoted = "## The built-in survey\n<!-- figure: t -->\n| lines | **18** | 22 |\n<!-- /figure -->\n"
    assert _unlisted_rows("docs/survey.md", quoted) == ([], set())


def test_the_hand_typed_row_check_sees_numbers_but_not_figures_or_code():
    text = ("## A\n| what | measured |\n| --- | --- |\n| x `--seeds 10` | the table below (`swarm.py --seeds 10`) |\n"
            "| y | <!-- figure: f -->3 s<!-- /figure --> (load in the figure) |\n| z 1-hour | 0.62 s wall |\n"
            "<!-- figure: t -->\n| 9 | 9 |\n<!-- /figure -->\n## Formation\n| one IABC plan on marcus-wake | 0.1 s |\n")
    assert _measured_rows(text) == [
        ("A", "z 1-hour", "| z 1-hour | 0.62 s wall |"),
        ("Formation", "one IABC plan on marcus-wake", "| one IABC plan on marcus-wake | 0.1 s |")]
    rows, _, labels = _hand_typed(text)
    assert rows == ["| z 1-hour | 0.62 s wall |"] and labels == {"one IABC plan on marcus-wake"}


def _bench_tool():
    spec = importlib.util.spec_from_file_location("figures_bench", ROOT / "tools" / "figures_bench.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_document_001_cells_count_and_summarise_the_runs_as_the_table_says():
    """arrived / with a collision (DL) · RMS median / max worst · least obstacle distance · time median."""
    run = {"scenario": "s", "law": "a", "compensation": False, "status": "EXACT", "arrived": True, "collisions": 0,
           "rms_m": 1.0, "max_m": 2.0, "min_obstacle_m": 3.0, "duration_s": 100.0}
    rows = [run, {**run, "rms_m": 3.0, "max_m": 9.25, "duration_s": 300.0},
            {**run, "status": "COLLISION", "arrived": False, "collisions": 1, "rms_m": 2.0, "min_obstacle_m": -0.5},
            {**run, "status": "DEADLOCK", "arrived": False, "rms_m": 5.0, "min_obstacle_m": float("inf")}]
    rows += [{**r, "compensation": True, "min_obstacle_m": float("inf")} for r in rows[:2]]
    table = _bench_tool().tracking_table(rows, ["s"], ["a"], {"a": "law A"}, default="a").splitlines()
    assert table[0] == "| law | crab | `s` |"
    assert table[2] == "| law A | no | 2 / 1 (1 DL) · 2.50 / 9.2 · −0.50 · 200 |"
    assert table[3] == "| law A (default) | yes | 2 / 0 · 2.00 / 9.2 · — · 200 |"


# The README's prose under the same guard: a measured-looking number (a count out of a total, a percentage,
# a multiple, an angle, an approximate duration) outside code, links, pictures and figure blocks fails.
MEASURED_IN_PROSE = re.compile(r"\d\s?/\s?\d|\d\s?%|\d\s?×|\d\s?°|(?:about|~)\s?\d|\d\s?(?:min|minutes)\b")


def _measured_prose(text: str) -> list[str]:
    """The number-bearing phrases of ``text``'s prose that look measured and are not quoted figures."""
    text = _tool().BLOCK.sub("", text)
    text = re.sub(r"```.*?```", "", text, flags=re.S)
    text = re.sub(r"!\[[^\]]*\]\([^)]*\)", "", text)  # pictures (their captions describe the picture)
    text = re.sub(r"\]\([^)]*\)", "]", text)  # link targets
    text = re.sub(r"`[^`]*`", "", text)
    return [text[max(0, m.start() - 30):m.end() + 10].replace("\n", " ") for m in MEASURED_IN_PROSE.finditer(text)]


def test_readme_has_no_hand_typed_measured_numbers():
    assert _measured_prose(README.read_text()) == [], \
        "hand-typed numbers: measure them into docs/figures/ and quote them with a marker, or drop them"


def test_the_readme_guard_catches_the_numbers_it_replaced():
    for typed in ("100/100 arrivals, 0 contacts", "within 0.18 % of its planned duration", "about 8 min on",
                  "the body is 1.045× the inflated", "(2.86° over a 0.5 m step", "numba off (~1 min)."):
        assert len(_measured_prose(f"- x: {typed}\n")) == 1, typed
    quoted = "- x: <!-- figure: f -->100/100 (0.18 %)<!-- /figure --> `--seeds 0/1` [a](docs/x1/2.md) ![5 %](p.png)\n"
    assert _measured_prose(quoted) == []
