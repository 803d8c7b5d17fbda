"""Every benchmark make target runs the command its committed figure states (text only: nothing is run)."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

ROOT = Path(__file__).parents[2]
FIGURES = ROOT / "docs" / "figures"
# options that only name where the results go: they do not change what is measured
OUTPUT_ONLY = {"--out", "--figure-md", "--figure"}


def _makefile() -> tuple[dict[str, str], dict[str, str]]:
    """The Makefile's ``?=`` defaults and each target's recipe (continuation lines joined, variables expanded)."""
    text = (ROOT / "Makefile").read_text().replace("\\\n", " ")
    defaults = dict(re.findall(r"^(\w+) \?= *(.*?)\s*$", text, re.M))
    recipes: dict[str, str] = {}
    for m in re.finditer(r"^([\w.-]+):[^\n=]*\n((?:\t[^\n]*\n?)*)", text, re.M):
        recipe = m.group(2)
        for name, value in defaults.items():
            recipe = recipe.replace(f"$({name})", value)
        recipes[m.group(1)] = recipe
    return defaults, recipes


def _options(command: str, script: str) -> dict[str, tuple[str, ...]]:
    """The options of ``script``'s command line in ``command``: ``--flag`` -> its values."""
    words = shlex.split(command)
    words = words[next(i for i, w in enumerate(words) if w.endswith(script)) + 1:]
    out: dict[str, tuple[str, ...]] = {}
    key = None
    for w in words:
        if w.startswith("--"):
            key = w
            out[key] = ()
        elif key is not None:
            out[key] = (*out[key], w)
    return out


def test_bench_hard_runs_the_figures_command() -> None:
    _, recipes = _makefile()
    recipe = next(line for line in recipes["bench-hard"].splitlines() if "benchmarks/hard.py" in line)
    made = _options(recipe, "benchmarks/hard.py")
    assert made["--figure-md"] == ("bench-hard-default",)
    stated = re.search(r"`(benchmarks/hard\.py [^`]*)`", (FIGURES / "bench-hard-default.md").read_text())
    assert stated is not None
    written = _options(stated.group(1), "benchmarks/hard.py")
    # the figure states the measurement's settings; the target passes exactly those (benchmarks/hard.py's
    # summary_figure leaves out the peer selection --no-peers/--methods, which select the figure's columns)
    assert written == {k: v for k, v in made.items() if k not in OUTPUT_ONLY | {"--no-peers", "--methods"}}
    assert made["--methods"] == ("iabc", "iabc/release") and "--no-peers" in made


def test_bench_regress_runs_against_the_figures_release() -> None:
    defaults, recipes = _makefile()
    text = (FIGURES / "bench-regress.md").read_text()
    prev = re.search(r"previous release \((\w+)\), measured in one run \(`make bench-regress`\)", text)
    assert prev is not None
    made = _options(recipes["bench-regress"], "benchmarks/regress.py")
    assert made["--prev"] == (prev.group(1),) == (defaults["PREV"],)
    assert made["--figure-md"] == ("bench-regress",)


def test_every_benchmark_figure_made_by_docs_figures_bench_is_a_make_step() -> None:
    _, recipes = _makefile()
    stated = {m for f in FIGURES.glob("*.md")
              for m in re.findall(r"`tools/docs_figures\.py bench ([\w-]+)`", f.read_text())}
    assert stated, "no figure states its docs_figures.py bench command"
    for name in stated:
        assert f"tools/docs_figures.py bench {name}\n" in recipes["docs-bench"], name
