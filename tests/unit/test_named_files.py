"""Every data file a scenario names, in one list (:func:`auvplan.io.scenario.specs.named_files`): what
``serve`` confines to its folders and what a departure sweep's checkpoints are keyed on.  Oracle: the
files written in the scenarios by hand."""

from __future__ import annotations

from dataclasses import replace

from auvplan.io.scenario import loader as sc
from auvplan.io.scenario.specs import named_files
from auvplan.survey.spec import SurveySpec


def test_zone_files_and_a_survey_centre_line_are_named():
    s = sc.load("chagos-reefs")  # its reefs are a [[zones]] file
    assert named_files(s) == [("[[zones]] #1 file", "../ne_10m_reefs_chagos.geojson")]
    s = replace(s, survey=SurveySpec(centerline_file="pipe.geojson", width_m=400.0))
    assert named_files(s)[-1] == ("[survey] centerline_file", "pipe.geojson")


def test_currents_tides_members_land_terrain_in_order():
    s = sc.loads("""
name = "files"
[origin]
lat = 48.2
lon = -123.5
[bounds]
x = [0.0, 2000.0]
y = [0.0, 2000.0]
z = [-100.0, 0.0]
[terrain]
file = "seabed.nc"
[currents]
file = "c.nc"
members = [{file = "m0.nc"}, {uniform = [0.1, 0.0, 0.0]}, {file = "m2.nc"}]
[land]
file = "coast.gpkg"
[mission]
start = [100.0, 100.0, -20.0]
goal = [1900.0, 1900.0, -20.0]
""", source="files.toml")
    assert named_files(s) == [("[terrain] file", "seabed.nc"), ("[currents] file", "c.nc"),
                              ("[currents] members[0] file", "m0.nc"),
                              ("[currents] members[2] file", "m2.nc"), ("[land] file", "coast.gpkg")]
    tidal = replace(s, currents=replace(s.currents, file=None, members=(), tides="station.json"))
    assert named_files(tidal) == [("[terrain] file", "seabed.nc"), ("[currents] tides", "station.json"),
                                  ("[land] file", "coast.gpkg")]
    assert named_files(replace(tidal, currents=replace(tidal.currents, tides="juan-de-fuca")))[1] == (
        "[land] file", "coast.gpkg")  # a built-in tide set is no file
