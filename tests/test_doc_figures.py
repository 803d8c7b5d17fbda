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

ROOT = Path(__file__).parents[1]
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
    assert {"demo-cost", "demo-flight", "missions", "gauntlet-predictive"} <= set(quoted)
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
