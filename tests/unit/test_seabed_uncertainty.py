"""Bathymetric uncertainty (issue 39): the worst-case seabed at a confidence and the clearance "x m at 95 %";
oracles are closed forms on a flat seabed with a known uncertainty layer."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from auvplan.cli import main
from auvplan.io.scenario import loader
from auvplan.world import Terrain
from auvplan.world.uncertainty import slope_sigma, worst_case, z_score

Z95 = 1.6448536269514722  # Φ⁻¹(0.95)
X = np.arange(0.0, 2001.0, 100.0)
SCEN = """
name = "uncertain"
[origin]
lat = 60.0
lon = 5.0
[bounds]
x = [0.0, 2000.0]
y = [0.0, 2000.0]
z = [-100.0, 0.0]
[terrain]
file = "seabed.nc"
uncertainty = "sigma"
[mission]
start = [200.0, 1000.0, -60.0]
goal = [1800.0, 1000.0, -60.0]
route = [[200.0, 1000.0, -60.0], [1800.0, 1000.0, -60.0]]
min_altitude_m = 10.0
confidence = 0.95
"""


def sigma_of(x):
    return 2.0 + 0.004 * x  # 2 m at x = 0 to 10 m at x = 2000


@pytest.fixture
def folder(tmp_path):
    gx, _ = np.meshgrid(X, X)
    ds = xr.Dataset({"elevation": (("y", "x"), np.full(gx.shape, -100.0), {"units": "m", "positive": "up"}),
                     "sigma": (("y", "x"), sigma_of(gx), {"units": "m"})},
                    coords={"x": ("x", X, {"units": "m"}), "y": ("y", X, {"units": "m"})})
    ds.to_netcdf(tmp_path / "seabed.nc")
    (tmp_path / "s.toml").write_text(SCEN)
    (tmp_path / "m.csv").write_text("x,y,z\n200,1000,-60\n1800,1000,-60\n")
    return tmp_path


def test_z_score():
    assert z_score(0.95) == pytest.approx(Z95, rel=1e-12)
    with pytest.raises(ValueError):
        z_score(1.0)


def test_worst_case_seabed_is_raised_by_the_layer(folder):
    world, _ = loader.build(loader.load(folder / "s.toml"))
    t = world.terrain
    gx, _ = np.meshgrid(t.x, t.y)
    assert t.z == pytest.approx(-100.0 + Z95 * sigma_of(gx), abs=1e-9)
    assert "worst case at 95 %" in t.name


def test_mission_check_reports_the_clearance_at_95_percent(folder, capsys):
    """Flat seabed at -100 m, route at -60 m: nominal altitude 40 m; the least worst-case clearance is at the
    route's east end, 40 - Φ⁻¹(0.95) σ(1800) = 40 - 1.6449 × 9.2 = 24.867 m."""
    expect = 40.0 - Z95 * sigma_of(1800.0)
    assert main(["mission", "check", str(folder / "m.csv"), "--scenario", str(folder / "s.toml")]) == 0
    out = capsys.readouterr().out
    assert f"clearance {expect:.2f} m at 95 %" in out
    assert main(["mission", "check", str(folder / "m.csv"), "--scenario", str(folder / "s.toml"), "--json"]) == 0
    import json

    rec = json.loads(capsys.readouterr().out)
    assert rec["min_altitude_m"] == pytest.approx(expect, abs=1e-6) and rec["clearance_confidence"] == 0.95


def test_a_route_too_low_for_the_confidence_fails(folder, capsys):
    """At 99.99 % the east end's worst case is -100 + 3.719 × 9.2 = -65.8 m: the route at -60 m keeps 5.8 m,
    below min_altitude_m = 10: the check fails (nominally it keeps 40 m; the scenario's own goal is at x = 1000, where
    the worst case leaves 17.7 m, and the scenario itself would refuse a goal at x = 1800)."""
    (folder / "s.toml").write_text(SCEN.replace("confidence = 0.95", "confidence = 0.9999").replace(
        "route = [[200.0, 1000.0, -60.0], [1800.0, 1000.0, -60.0]]\n", "").replace(
        "goal = [1800.0, 1000.0, -60.0]", "goal = [1000.0, 1000.0, -60.0]"))
    assert main(["mission", "check", str(folder / "m.csv"), "--scenario", str(folder / "s.toml")]) == 1
    out = capsys.readouterr().out
    assert f"clearance {40.0 - z_score(0.9999) * sigma_of(1800.0):.2f} m at 99.99 %" in out


def test_slope_rule_closed_form():
    """A plane of slope 0.1 on a 100 m grid: σ = √(σ0² + (100 × 0.1 / 2)²) = √(4 + 25) everywhere."""
    x = np.arange(0.0, 1001.0, 100.0)
    gx, _ = np.meshgrid(x, x)
    t = Terrain(x, x, -200.0 + 0.1 * gx)
    assert slope_sigma(t, 2.0) == pytest.approx(np.sqrt(29.0), rel=1e-12)
    w = worst_case(t, slope_sigma(t, 2.0), 0.95)
    assert w.z - t.z == pytest.approx(Z95 * np.sqrt(29.0), rel=1e-12)


@pytest.mark.parametrize("key, value", [("confidence", "1.5"), ("confidence", "0.3")])
def test_bad_confidence_exits_2(folder, capsys, key, value):
    (folder / "s.toml").write_text(SCEN.replace("confidence = 0.95", f"{key} = {value}"))
    assert main(["validate", str(folder / "s.toml")]) == 2
    err = capsys.readouterr().err
    assert "s.toml" in err and key in err and value in err


def test_confidence_without_uncertainty_is_refused(folder, capsys):
    (folder / "s.toml").write_text(SCEN.replace('uncertainty = "sigma"\n', ""))
    assert main(["validate", str(folder / "s.toml")]) == 2
    assert "no vertical uncertainty" in capsys.readouterr().err
