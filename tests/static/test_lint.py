"""Static checks run as tests: ruff, and the import-linter layers contract of DESIGN.md §2."""

from __future__ import annotations

import subprocess

from lint_runs import ROOT, verdict
from lint_runs import tool as _tool


def test_ruff_clean():
    r = subprocess.run([_tool("ruff"), "check", "src", "tests", "benchmarks"], cwd=ROOT, capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr


def test_import_layers_kept():
    r = subprocess.run([_tool("lint-imports"), "--no-cache"], cwd=ROOT, capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "broken" in r.stdout and "0 broken" in r.stdout


def test_mypy_clean():
    """``mypy`` with the configuration of pyproject.toml ([tool.mypy], ``strict = true``): the whole of src/
    under mypy --strict (the exceptions are listed there).  In the whole suite the run is started as soon as
    the tests are collected and goes on beside them (tests/static/lint_runs.py); the test waits for its verdict."""
    code, output = verdict("mypy")
    assert code == 0, output
