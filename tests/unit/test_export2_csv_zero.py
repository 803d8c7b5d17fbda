"""``mission.csv`` writes a waypoint at the surface at depth ``0.000``, never ``-0.000`` (helper export2, wave 17).

A surface fix's depth is ``-z`` of ``z = -0.0`` (``max(z_route, -tanθ·0)``), which ``f"{-z:.3f}"`` printed as
``-0.000``; so did any value within half a millimetre of zero of either sign.  Oracle: the written text (no
``-0.000`` in any metric column) and each cell read back equal to the value rounded to the millimetre.
"""

from __future__ import annotations

import csv
import io

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
