"""Geographic positions are projected once (issue 56): a scenario's lat/lon points and survey area, and a tide
file's stations and flood/ebb directions, are kept in the readers' cache (pyproj's own numbers), so a scenario
parsed before imports no pyproj.  Oracle: the same scenario and tidal current, with the projection refused."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.io.data import geo
from auvplan.io.data.ocean.tides import load_tidal_current, parse_start_time
from auvplan.io.scenario import loader


def _refuse(*_args, **_kwargs):
    raise AssertionError("projected again")


def test_positions_and_tide_directions_are_projected_once(tmp_path, monkeypatch) -> None:
    monkeypatch.setenv("AUVPLAN_CACHE_DIR", str(tmp_path))
    monkeypatch.delenv("AUVPLAN_CACHE", raising=False)
    corridor = loader.load("strait-corridor")  # lat/lon positions, the box derived round a survey area file
    tide = loader.load("rotary-tide")
    frame = geo.LocalFrame(tide.origin.lat, tide.origin.lon)

    def tidal():
        return load_tidal_current(tide.currents.tides, frame, parse_start_time(tide.mission.start_time),
                                  base_dir=tide.base_dir)

    first = tidal()
    monkeypatch.setattr(geo.LocalFrame, "_transformer", _refuse)  # no projection from here on
    assert repr(loader.load("strait-corridor")) == repr(corridor)
    again = tidal()
    for name in ("site_xy", "flood", "ebb"):
        assert np.array_equal(getattr(again, name), getattr(first, name)), name
    monkeypatch.setenv("AUVPLAN_CACHE", "0")  # the cache off: projected, so refused
    with pytest.raises(AssertionError, match="projected again"):
        loader.load("strait-corridor")
