"""A ``[[zones]] file`` whose ``where`` filter (docs/zones.md) selects nothing (docwalk 18): the warning said "no
feature reaches the operating area" — features too far away — when the filter matched none; now it says the
filter matched no feature.  A feature in the area that the filter keeps is a zone (the oracle of the filter)."""

from __future__ import annotations

import json
import logging
from pathlib import Path

import pytest

from auvplan.io.data.geo import LocalFrame
from auvplan.io.data.vector.zones import parse_zones, read_zones

FRAME = LocalFrame(48.0, -125.0)


def _chart(tmp_path: Path) -> None:
    """Two 100 m squares in the area, named 'A' (category 1) and 'B' (category 2)."""
    def square(x: float) -> list[list[float]]:
        lon, lat = FRAME.inverse([x, x + 100, x + 100, x, x], [500.0, 500.0, 600.0, 600.0, 500.0])
        return [[float(a), float(b)] for a, b in zip(lon, lat, strict=True)]

    doc = {"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"name": n, "cat": c}, "geometry": {"type": "Polygon",
                                                                             "coordinates": [square(x)]}}
        for n, c, x in (("A", 1, 500.0), ("B", 2, 1200.0))]}
    (tmp_path / "chart.geojson").write_text(json.dumps(doc))


def _zones(tmp_path: Path, where: str):  # type: ignore[no-untyped-def]
    specs = parse_zones([{"name": "chart", "file": "chart.geojson", "where": where}], "s.toml")
    return read_zones(specs, FRAME, None, (0.0, 2000.0, 0.0, 2000.0), base_dir=tmp_path)


def test_a_filter_that_selects_nothing_is_said_as_such(tmp_path: Path, caplog: pytest.LogCaptureFixture) -> None:
    _chart(tmp_path)
    with caplog.at_level(logging.WARNING):
        assert list(_zones(tmp_path, "cat = 2").names) == ["chart: B"]
        assert not caplog.records
        assert len(_zones(tmp_path, "cat = 3").names) == 0
    assert [r.getMessage() for r in caplog.records] == [  # was "no feature reaches the operating area"
        f"s.toml: [[zones]] #1 file = '{tmp_path / 'chart.geojson'}': no feature matches where = 'cat = 3'"]


def test_a_zone_outside_the_area_says_how_its_pairs_were_read() -> None:
    """docs/zones.md's example pasted into another area: its [lat, lon] pairs were said to be "read as metres"."""
    from auvplan.errors import AuvplanError

    far = [[48.5, -125.5], [48.5, -125.4], [48.6, -125.4]]  # degrees, 60 km from the 2 km area: read as degrees
    with pytest.raises(AuvplanError, match=r"outside the operating area .*; its pairs were read as \[lat, lon\] about "
                                           r"\[origin\] lat = 48, lon = -125$"):
        read_zones(parse_zones([{"name": "range", "polygon": far}], "s.toml"), FRAME, None, (0.0, 2000.0, 0.0, 2000.0))
    metres = [[90000.0, 0.0], [91000.0, 0.0], [91000.0, 1000.0]]  # metres, 90 km away: the hint stays
    with pytest.raises(AuvplanError, match=r"read as metres \[x, y\], not all being within 5° of \[origin\]"):
        read_zones(parse_zones([{"name": "range", "polygon": metres}], "s.toml"), FRAME, None,
                   (0.0, 2000.0, 0.0, 2000.0))


def test_a_zone_table_without_a_name_is_said_to_have_none() -> None:
    from auvplan.errors import AuvplanError

    with pytest.raises(AuvplanError, match=r"^s\.toml: \[\[zones\]\] #1 has no name: every zone needs one"):
        parse_zones([{"point": [100.0, 100.0], "radius_m": 5.0}], "s.toml")  # was "name = '': expected a non-empty"
    with pytest.raises(AuvplanError, match=r"name = '': expected a non-empty string"):
        parse_zones([{"name": "", "point": [100.0, 100.0], "radius_m": 5.0}], "s.toml")
