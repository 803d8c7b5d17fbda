"""A CSV mission's ``speed`` column edited by hand (docwalk 18): one empty cell dropped every speed the column
carries — all legs judged at the vehicle's speed under the line "leg speeds not in the file" — and a speed of 0
or below did the same silently.  Now an empty cell is that leg's speed only (judged at the vehicle's, named in
``assumed_legs``), and 0 or below exits 2 naming the leg.  Oracle: the speeds written by ``mission_csv`` itself.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from auvplan.errors import DataError
from auvplan.io.missions.formats import mission_csv
from auvplan.io.missions.readback.speeds import judged_leg_speeds

POINTS = np.array([[0.0, 0.0, -20.0], [500.0, 0.0, -30.0], [900.0, 300.0, -30.0], [900.0, 900.0, -25.0],
                   [1500.0, 900.0, -40.0]])
LEGS = np.array([0.8, 1.7, 1.2, 1.4])  # per leg: the CSV's rows 1..4 (row 0 repeats leg 0's)


def _csv(tmp_path: Path, cell: dict[int, str]) -> Path:
    """``mission_csv``'s file with the ``speed`` cells of the given waypoint rows replaced."""
    lines = mission_csv(POINTS, (48.0, -125.0), LEGS).splitlines()
    col = lines[0].split(",").index("speed")
    for row, value in cell.items():
        parts = lines[row + 1].split(",")
        parts[col] = value
        lines[row + 1] = ",".join(parts)
    path = tmp_path / "m.csv"
    path.write_text("\n".join(lines) + "\n")
    return path


def test_the_written_speeds_are_read_back(tmp_path: Path) -> None:
    got = judged_leg_speeds(_csv(tmp_path, {}), 4, 1.5)
    np.testing.assert_allclose(got.speeds, LEGS)
    assert got.assumed_legs == () and got.line == ""


def test_an_empty_speed_cell_is_that_legs_speed_only(tmp_path: Path) -> None:
    got = judged_leg_speeds(_csv(tmp_path, {3: ""}), 4, 1.5)  # the row reaching waypoint 3: leg 2
    np.testing.assert_allclose(got.speeds, [0.8, 1.7, 1.5, 1.4])  # was [1.5] * 4
    assert got.assumed_legs == (2,)
    assert got.line == "leg speeds not in the file: judged at the vehicle's speed 1.5 m/s (legs 2)"


@pytest.mark.parametrize("value", ["0", "-1.5"])
def test_a_speed_not_positive_is_refused_naming_the_leg(tmp_path: Path, value: str) -> None:
    with pytest.raises(DataError, match=rf"m\.csv: leg 1's speed {value} m/s \(carried by the file\) is not positive"):
        judged_leg_speeds(_csv(tmp_path, {2: value}), 4, 1.5)  # was: every leg at 1.5 m/s, "not in the file"


@pytest.mark.parametrize("value", ["abc", "1.5 m/s", "fast"])
def test_a_speed_that_is_not_a_number_is_refused_naming_the_line_and_value(tmp_path: Path, value: str) -> None:
    """A typed-in word was read as 'no speed column': every leg judged at the vehicle's speed, silently."""
    with pytest.raises(DataError, match=rf"m\.csv: line 4: speed = '{value}' is not a number"):
        judged_leg_speeds(_csv(tmp_path, {2: value}), 4, 1.5)  # the file's line 4: header, then rows 0, 1, 2
