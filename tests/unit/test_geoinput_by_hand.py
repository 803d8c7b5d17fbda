"""Geographic input at its edges by hand (issue 49's mutation run of ``geoinput``): the ranges' closed ends, a
``[bounds]`` that gives only depths, and the derived box around a survey area."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.errors import ScenarioError
from auvplan.io.data.geo import LocalFrame
from auvplan.io.scenario.inputs.geoinput import _geo_point, bounds_margin, resolve_positions


@pytest.mark.parametrize("value", [{"lat": 90.0, "lon": 0.0, "depth": 5.0}, {"lat": -90.0, "lon": 0.0, "depth": 5.0},
                                   {"lat": 0.0, "lon": -360.0, "depth": 5.0}, {"lat": 0.0, "lon": 360.0, "depth": 5.0},
                                   {"lat": 0.0, "lon": 0.0, "altitude": 0.0}])
def test_the_ranges_include_their_ends(value) -> None:  # type: ignore[no-untyped-def]
    assert _geo_point("t.toml", "start", value)[:2] == (value["lat"], value["lon"])


@pytest.mark.parametrize("key, value", [("lat", 90.5), ("lat", -90.5), ("lon", 360.5), ("altitude", -0.5)])
def test_just_beyond_each_end_is_refused_naming_the_key(key, value) -> None:  # type: ignore[no-untyped-def]
    point = {"lat": 0.0, "lon": 0.0, "depth": 5.0}
    if key == "altitude":
        point = {"lat": 0.0, "lon": 0.0, "altitude": value}
    else:
        point[key] = value
    with pytest.raises(ScenarioError, match=rf"start\.{key}"):
        _geo_point("t.toml", "start", point)


def _mission(lat: float, lon: float) -> dict:  # type: ignore[type-arg]
    return {"start": {"lat": lat, "lon": lon, "depth": 50.0}, "goal": {"lat": lat + 0.001, "lon": lon, "depth": 50.0}}


def test_bounds_with_depths_only_get_derived_sides() -> None:
    g = resolve_positions({"mission": _mission(14.0, 158.0), "bounds": {"z": [-300.0, 0.0]}}, "t.toml")
    assert g is not None and g.bounds_derived and g.metric["bounds"]["z"] == [-300.0, 0.0]
    assert {"x", "y"} <= set(g.metric["bounds"])
    kept = resolve_positions({"mission": _mission(14.0, 158.0), "bounds": {"y": [-9.0, 9.0]}}, "t.toml")
    assert kept is not None and not kept.bounds_derived and kept.metric["bounds"] == {"y": [-9.0, 9.0]}


def test_the_derived_box_holds_the_survey_area_and_its_swath() -> None:
    """The mission inside a 0.2° by 0.02° survey area with 200 m swaths: the box is the area's projected extent
    ± 100 m (half a swath), plus the margin of its larger (north-south) side, 25 % of 22 km, on every side."""
    poly = [[14.0, 158.02], [14.2, 158.02], [14.2, 158.04], [14.0, 158.04]]  # (lat, lon): 22 km by 2.2 km
    data = {"mission": _mission(14.1, 158.03), "survey": {"polygon": poly, "width_m": 200.0}}
    g = resolve_positions(data, "t.toml")
    assert g is not None and g.bounds_derived and g.origin is not None
    sx, sy = LocalFrame(*g.origin).forward(np.array([p[1] for p in poly]), np.array([p[0] for p in poly]))
    x0, x1, y0, y1 = sx.min() - 100.0, sx.max() + 100.0, sy.min() - 100.0, sy.max() + 100.0
    pad = bounds_margin(max(x1 - x0, y1 - y0))
    assert g.metric["bounds"]["x"] == pytest.approx([x0 - pad, x1 + pad], abs=1e-6)
    assert g.metric["bounds"]["y"] == pytest.approx([y0 - pad, y1 + pad], abs=1e-6)
