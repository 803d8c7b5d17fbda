"""plotly is an optional extra (``auvplan[report]``): without it the commands that write an HTML report say so
in one line and exit 2 before doing any work, the rest of the package (static figures, validation) still works,
and importing the report module names the extra to install.  plotly is blocked by ``sys.modules['plotly'] =
None``, which makes every ``import plotly...`` fail as it does when the package is absent."""

from __future__ import annotations

import importlib
import sys

import numpy as np
import pytest

import auvplan.viz
from auvplan.cli import main

_VIZ = ("chart", "plots", "report", "scene3d", "style", "timeplots")


@pytest.fixture
def no_plotly(monkeypatch):
    """plotly made unimportable; the viz modules re-imported under that, everything restored afterwards.

    A module first imported while plotly is blocked (``auvplan.viz.scene3d`` when this file runs first) holds
    plotly's stand-in: it is dropped from ``sys.modules`` and from its package at teardown, so that the next
    import loads it with plotly (monkeypatch restores only what was there before)."""
    before = set(sys.modules)
    for name in list(sys.modules):
        if name == "plotly" or name.startswith("plotly.") or name in {f"auvplan.viz.{m}" for m in _VIZ}:
            monkeypatch.delitem(sys.modules, name)
    for m in _VIZ:  # the package attributes that a re-import rebinds
        if hasattr(auvplan.viz, m):
            monkeypatch.setattr(auvplan.viz, m, getattr(auvplan.viz, m))
    monkeypatch.setitem(sys.modules, "plotly", None)
    with pytest.raises(ImportError):
        import plotly  # noqa: F401
    yield
    for name in set(sys.modules) - before:  # only the viz modules can hold the stand-in: a module of another
        # package first imported here (``run`` loads ``auvplan.sim.pipeline``) stays, or its package's lazily bound
        # names (``auvplan.sim.planning_problem``) would outlive it and differ from a re-import's
        if sys.modules[name] is not None and name.startswith(("plotly.", "auvplan.viz.")):
            module = sys.modules.pop(name)
            parent, _, leaf = name.rpartition(".")
            if getattr(sys.modules.get(parent), leaf, None) is module:
                delattr(sys.modules[parent], leaf)


def _one_line_error(capsys) -> str:
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    return err


@pytest.mark.parametrize("argv", [["demo", "--out", "{tmp}/demo"], ["run", "marcus-wake", "--out", "{tmp}/run"],
                                  ["report", "{tmp}/missing"], ["bench", "--out", "{tmp}/bench", "--seeds", "1"]])
def test_html_commands_exit_2_with_one_line_before_any_work(no_plotly, argv, tmp_path, capsys):
    assert main([a.format(tmp=tmp_path) for a in argv]) == 2
    err = _one_line_error(capsys)
    assert "plotly" in err and "pip install 'auvplan[report]'" in err
    assert list(tmp_path.iterdir()) == []  # nothing written, nothing computed


def test_commands_without_html_still_work(no_plotly, capsys):
    assert main(["validate", "marcus-wake"]) == 0
    assert main(["scenarios"]) == 0


def test_static_figures_need_no_plotly(no_plotly):
    plots = importlib.import_module("auvplan.viz.plots")
    fig = plots.convergence({"iabc": [3.0, 2.0, 1.5]})
    assert len(fig.axes) == 1 and fig.axes[0].lines[0].get_ydata().tolist() == [3.0, 2.0, 1.5]
    scene3d = importlib.import_module("auvplan.viz.scene3d")  # its geometry helpers are plotly-free
    from auvplan.world import Sphere

    x, y, z = scene3d.shape_surface(Sphere((0.0, 0.0, -50.0), 10.0), 9)
    assert np.allclose(np.sqrt(x**2 + y**2 + (z + 50.0) ** 2), 10.0)
    with pytest.raises(ImportError, match=r"auvplan\[report\]"):
        scene3d.go.Figure()


def test_report_module_names_the_extra(no_plotly):
    with pytest.raises(ImportError, match=r"pip install 'auvplan\[report\]'"):
        importlib.import_module("auvplan.viz.report")


def test_extras_declared_and_all_installs_them():
    """``make`` installs ``.[all,test]``: ``all`` must pull in every optional feature."""
    import tomllib
    from pathlib import Path

    meta = tomllib.loads((Path(__file__).resolve().parents[2] / "pyproject.toml").read_text())["project"]
    assert not any(d.startswith(("plotly", "dask")) for d in meta["dependencies"])
    extras = meta["optional-dependencies"]
    assert any(d.startswith("plotly") for d in extras["report"])
    assert "auvplan[bench,report]" in extras["all"]


def test_no_stand_in_outlives_the_blocking():
    """Runs after the tests that block plotly (pytest keeps the file's order): every viz module loaded now has the
    real plotly.  With this file run first, scene3d is first imported while plotly is blocked; it kept plotly's
    stand-in for every later test until the fixture dropped what was first imported under the block."""
    import plotly.graph_objects as go

    from auvplan.viz import scene3d

    assert sys.modules["plotly"] is not None
    assert scene3d.go is go and sys.modules["auvplan.viz.scene3d"] is scene3d
    assert scene3d is importlib.import_module("auvplan.viz.scene3d")
    for name, module in list(sys.modules.items()):
        if name.startswith("auvplan.viz.") and hasattr(module, "go"):
            assert module.go is go, name
