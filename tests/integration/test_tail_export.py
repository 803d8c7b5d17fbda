"""Tail-first legs leave auvplan only in files that say so, and come back from them.

A ``rotary-tide`` mission leaving at +18 h (no forward path; ``tail_first`` plans legs flown heading
against the track) is exported.  Oracles: each carrying format (CSV, GeoJSON, KML, ROS Path) reads back
the route's own flags (:func:`auvplan.sim.record_tail`) and waypoints; the energy check of each file is
the analysis of the run (``assess`` with the flags), while the same file without its flags is
INFEASIBLE (what every file said before); MOOS, QGroundControl and GPX are refused in one line naming
the legs; a mission without tail-first legs is written byte for byte as before; the flags survive
``run.npz``.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from auvplan._types import Status
from auvplan.endurance import assess
from auvplan.errors import DataError
from auvplan.io.missions import export
from auvplan.io.missions import formats as mfmt
from auvplan.io.missions.energy import mission_file_energy
from auvplan.io.missions.readback.readers import read_mission
from auvplan.io.missions.tail import TAIL_FORMATS, read_tail
from auvplan.io.results.readback import read_run
from auvplan.io.results.records import write_run
from auvplan.io.scenario import loader as scenario
from auvplan.sim import RunRecord, planned_route, record_tail


@pytest.fixture(scope="module")
def tail_run():
    sc = scenario.load("rotary-tide")
    world, mission = scenario.build(replace(sc, mission=replace(sc.mission, start_time="2026-06-16T15:00:00Z")))
    mission = replace(mission, planner=replace(mission.planner, timeopt=replace(mission.planner.timeopt,
                                                                                tail_first=True, method="lattice")))
    planned, route = planned_route(world, mission, mission.seed)
    assert planned is not None and route is not None
    record = RunRecord(mission.name, mission.seed, planned, route, route[[0, -1]], None)
    tail = record_tail(record)
    assert tail is not None and 0 < tail.sum() < tail.size
    return world, mission, record, tail


def test_carrying_formats_round_trip_the_flags_and_budget_as_flown(tail_run, tmp_path: Path):
    world, mission, record, tail = tail_run
    written = export.write_exports(tmp_path, record, world.origin, mission.vehicle.speed,
                                   [f for f in export.EXPORT_FORMATS if f in TAIL_FORMATS])
    assert sorted(p.suffix[1:] for p in written) == sorted(TAIL_FORMATS)
    expect = assess(world, record.route, mission.vehicle, mission.endurance, tail=tail).budget
    assert expect.status is Status.EXACT
    for path in written:
        w = read_mission(path, world.origin)[0]
        np.testing.assert_allclose(w, record.route, atol=1e-3)
        np.testing.assert_array_equal(read_tail(path, len(w) - 1), tail)
        rec, ok, _ = mission_file_energy(world, mission, path)
        assert ok and rec["energy_status"] == "EXACT", path
        assert rec["duration_s"] == pytest.approx(expect.duration_s, rel=1e-6)
        assert rec["energy_wh"] == pytest.approx(expect.energy_wh, rel=1e-6)
    stripped = tmp_path / "stripped.csv"  # the CSV without its column: every leg nose-first, as before
    stripped.write_text("\n".join(",".join(r.split(",")[:-1]) for r in (tmp_path / "mission.csv").read_text()
                                  .splitlines()) + "\n")
    assert read_tail(stripped, len(tail)) is None
    assert mission_file_energy(world, mission, stripped)[0]["energy_status"] == "INFEASIBLE"


@pytest.mark.parametrize("fmt", ["moos", "plan", "gpx"])
def test_formats_that_fly_every_leg_nose_first_are_refused(tail_run, tmp_path: Path, fmt: str):
    world, mission, record, tail = tail_run
    first = int(np.flatnonzero(tail)[0])
    with pytest.raises(DataError, match=rf"mission\.{fmt} not written: .* legs? {first}\b"):
        export.write_exports(tmp_path, record, world.origin, mission.vehicle.speed, [fmt])
    assert not any(tmp_path.iterdir())
    kept, notes = export.exportable(record, export.EXPORT_FORMATS)
    assert kept == [f for f in export.EXPORT_FORMATS if f in TAIL_FORMATS] and len(notes) == 3
    assert all("\n" not in n for n in notes)


def test_without_tail_first_legs_the_files_are_unchanged(tail_run):
    world, mission, record, tail = tail_run
    none = np.zeros_like(tail)
    w = record.route
    assert mfmt.mission_csv(w, world.origin, 1.5, none) == mfmt.mission_csv(w, world.origin, 1.5)
    assert mfmt.to_ros_path(w, 1.5, tail=none) == mfmt.to_ros_path(w, 1.5)
    forward = replace(record, plan=replace(record.plan, tail=None))
    assert export.exportable(forward, export.EXPORT_FORMATS) == (list(export.EXPORT_FORMATS), [])
    assert "tail_first_legs" not in export.to_kml(forward, world.origin)


def test_run_npz_keeps_the_flags(tail_run, tmp_path: Path):
    world, mission, record, tail = tail_run
    write_run(tmp_path, record, "", origin=world.origin)
    back, _ = read_run(tmp_path)
    assert back.plan is not None and back.plan.tail is not None
    np.testing.assert_array_equal(back.plan.tail, record.plan.tail)
    np.testing.assert_array_equal(record_tail(back), tail)


def test_read_tail_of_a_malformed_file_says_nothing(tmp_path: Path):
    """A file that does not parse carries no flags (None), never a traceback; the reader of the waypoints
    names the file (auvplan.io.missions.readback.readers)."""
    for name, text in (("m.yaml", "poses: [\n"), ("m.csv", "x,y\n1"), ("m.kml", "<kml"), ("m.geojson", "{")):
        (tmp_path / name).write_text(text)
        assert read_tail(tmp_path / name, 3) is None
