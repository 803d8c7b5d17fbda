"""``mission.csv`` writes a waypoint at the surface at depth ``0.000``, never ``-0.000`` (helper export2, wave 17).

A surface fix's depth is ``-z`` of ``z = -0.0`` (``max(z_route, -tanθ·0)``), which ``f"{-z:.3f}"`` printed as
``-0.000``; so did any value within half a millimetre of zero of either sign.  Oracle: the written text (no
``-0.000`` in any metric column) and each cell read back equal to the value rounded to the millimetre.
"""

from __future__ import annotations

import csv
import io
import math

import numpy as np

from auvplan.io.missions.formats import mission_csv

POINTS = np.array([[0.0, 0.0, -0.0], [100.0, -0.0004, -20.0], [200.0, 0.0, 0.0003], [300.0, 0.0, -0.0004],
                   [400.0, 0.0, -0.0], [500.0, 0.0, -1.2345]])


def test_no_negative_zero_in_the_csv():
    text = mission_csv(POINTS, (10.0, 20.0), 1.5)
    assert "-0.000" not in text, text
    rows = list(csv.DictReader(io.StringIO(text)))
    for r, p in zip(rows, POINTS, strict=True):
        assert float(r["depth"]) == round(-p[2], 3) and float(r["z"]) == round(p[2], 3)
        assert float(r["y"]) == round(p[1], 3)
    assert [r["depth"] for r in rows][:5] == ["0.000", "20.000", "0.000", "0.000", "0.000"]
    assert rows[2]["z"] == "0.000" and rows[1]["y"] == "0.000"


def test_no_negative_zero_in_the_other_metric_exports(tmp_path):
    """The same in ``mission.yaml`` (positions), ``.gpx`` (``ele``), ``.kml`` and ``.geojson`` (altitudes): a surface
    fix was ``z: -0.000`` / ``<ele>-0.000</ele>`` / ``,-0.000`` / ``-0.0``."""
    import json
    import re

    from auvplan.io.missions import export
    from auvplan.sim.result import RunRecord

    record = RunRecord("zero", 1, None, POINTS, POINTS[1:2], None)
    export.write_exports(tmp_path, record, (10.0, 20.0), 1.5, ("yaml", "gpx", "kml", "geojson"))
    for fmt in ("yaml", "gpx", "kml"):
        text = (tmp_path / f"mission.{fmt}").read_text()
        if fmt == "yaml":  # the positions (not the orientations' quaternions)
            text = " ".join(re.findall(r"position: \{[^}]*\}", text))
        assert not re.findall(r"-0\.0+(?!\d)", text), fmt
        assert len(re.findall(r"(?<![\d.])0\.000(?!\d)", text)) >= 4, fmt  # the surface points, written as 0.000
    doc = json.loads((tmp_path / "mission.geojson").read_text())
    z = [c[2] for f in doc["features"] if f["geometry"]["type"] == "LineString" for c in f["geometry"]["coordinates"]]
    assert all(math.copysign(1.0, v) > 0 for v in z if v == 0.0) and 0.0 in z
