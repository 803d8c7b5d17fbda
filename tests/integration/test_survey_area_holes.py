"""A survey area read from a file: its holes are refused, its other polygons said (wave 18).

The reader took the exterior ring of the layer's largest polygon: a hole in it (an exclusion cut out of the area in
a GIS) was surveyed all the same, and the layer's other polygons were left out, both without a word.  Now a hole is
bad input (exit 2, one line naming the file and the key, and what to do: [[zones]]), and polygons left out are
said in a warning.

Oracle: the files are written here with a known number of holes and polygons; the scenario is the survey tests' own
(``test_survey_mission``) with the same area as a polygon in a file.
"""

from __future__ import annotations

import json
import logging

import numpy as np
import pytest
from test_survey_mission import _write

from auvplan.cli import main
from auvplan.errors import ScenarioError
from auvplan.io.data.geo import LocalFrame
from auvplan.io.data.vector.areas import read_area_lonlat

FRAME = LocalFrame(48.0, -125.0)  # the survey tests' [origin]


def _ring(x0: float, x1: float, y0: float, y1: float, reverse: bool = False) -> list[list[float]]:
    x, y = np.array([x0, x1, x1, x0, x0]), np.array([y0, y0, y1, y1, y0])
    if reverse:
        x, y = x[::-1], y[::-1]
    lon, lat = FRAME.inverse(x, y)
    return [[float(a), float(b)] for a, b in zip(lon, lat)]


def _file(tmp_path, polygons: list[list[list[list[float]]]]):
    feats = [{"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": rings}}
             for rings in polygons]
    path = tmp_path / "area.geojson"
    path.write_text(json.dumps({"type": "FeatureCollection", "features": feats}))
    return path


AREA = _ring(400.0, 1400.0, 400.0, 1000.0)


@pytest.mark.parametrize("holes", [1, 2])
def test_an_area_with_holes_is_refused_naming_them(tmp_path, capsys, holes):
    inner = [_ring(500.0 + 300.0 * k, 700.0 + 300.0 * k, 500.0, 700.0, reverse=True) for k in range(holes)]
    path = _file(tmp_path, [[AREA, *inner]])
    with pytest.raises(ScenarioError, match=f"the area has {holes} hole"):
        read_area_lonlat(path, "", "t.toml: [survey]")
    scen = _write(tmp_path, area='file = "area.geojson"')
    assert main(["survey", str(scen)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "[survey] file = " in err and f"{holes} hole(s)" in err and "[[zones]]" in err


def test_the_polygons_left_out_are_said(tmp_path, caplog):
    small = _ring(1500.0, 1600.0, 400.0, 500.0)
    path = _file(tmp_path, [[AREA], [small]])
    with caplog.at_level(logging.WARNING, logger="auvplan"):
        ring = read_area_lonlat(path, "", "t.toml: [survey]")
    assert ring.shape == (5, 2) and np.allclose(ring, np.array(AREA))  # the largest, as documented
    assert any("2 polygons in the layer" in r.getMessage() and "other 1 are left out" in r.getMessage()
               for r in caplog.records)
    caplog.clear()
    with caplog.at_level(logging.WARNING, logger="auvplan"):
        read_area_lonlat(_file(tmp_path, [[AREA]]), "", "t.toml: [survey]")
    assert not [r for r in caplog.records if "left out" in r.getMessage()]
