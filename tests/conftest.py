"""Shared fixtures: the real built-in worlds (built once per session) and small synthetic scenes."""

from __future__ import annotations

import os

# OpenBLAS's worker threads spin while they wait: on a loaded 2-core machine each small LAPACK call (scipy's
# Delaunay barycentric transforms under LinearNDInterpolator, small solves) then costs up to seconds of CPU
# instead of microseconds (a 551-node curvilinear current regridded: 1.7 s CPU with the default threads,
# 0.002 s with one).  Set before numpy is imported; subprocesses inherit it.
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import contextlib  # noqa: E402
import io  # noqa: E402
import json  # noqa: E402

import pytest  # noqa: E402

from auvplan.io.scenario import loader as sc  # noqa: E402


@pytest.fixture(scope="session")
def marcus():
    """(Scenario, World, Mission) of the real marcus-wake scenario."""
    s = sc.load("marcus-wake")
    w, m = sc.build(s)
    return s, w, m


@pytest.fixture(scope="session")
def salish():
    """(Scenario, World, Mission) of the real salish-shelf scenario."""
    s = sc.load("salish-shelf")
    w, m = sc.build(s)
    return s, w, m


@pytest.fixture(scope="session")
def jdf_sweeps(tmp_path_factory):
    """The departure sweep of juan-de-fuca-tides over two departures (+0h, +6h: 2 x ~5 s of label search at CI),
    run once per session through ``auvplan.cli.main`` and shared by the tests of its CLI (test_timeopt) and of its
    progress (test_progress): ``{"text": (stdout, stderr), "json": (document, stderr, out folder)}``, the first as
    a person reads it, the second under ``--json --out`` with the end given as an absolute time."""
    from auvplan.cli import main

    runs = {}
    out = tmp_path_factory.mktemp("jdf-sweep")
    for kind, extra in (("text", ["+6h"]), ("json", ["2026-06-15T06:00:00Z", "--out", str(out), "--json"])):
        stdout, stderr = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
            code = main(["plan", "juan-de-fuca-tides", "--depart-between", "+0h", extra[0], "--step", "6h",
                         *extra[1:]])
        assert code == 0, stderr.getvalue()
        runs[kind] = (stdout.getvalue(), stderr.getvalue())
    text_out, json_err = runs["json"]
    return {"text": runs["text"], "json": (json.loads(text_out), json_err, out)}
