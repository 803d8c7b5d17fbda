"""The exported mission files carry the wait at each surface fix (``surface_s``) and ``mission check`` reads it
back from the file (``docs/navigation.md``; helper nav22).

Oracle: the plan's own flight through the current with its dwells (``auvplan.endurance.mission_budget`` with
``NavPlan.dwell_s``); the waits read back from a ``.plan`` (param 1 of each surfacing's ``NAV_WAYPOINT``) and a
MOOS file (a ``BHV_StationKeep`` per surfacing) sit at the plan's surface fixes and nowhere else; a file whose
waits are removed is budgeted without them (the file, not the scenario).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from auvplan.cli import main
from auvplan.endurance import EnergyModel
from auvplan.endurance import mission_budget as energy_budget
from auvplan.io.missions import export
from auvplan.io.missions.readback.dwell import moos_dwells, read_dwells
from auvplan.sim.result import RunRecord


@pytest.fixture(scope="module")
def mariana(tmp_path_factory, mariana_nav_plan):
    world, mission, _, plan = mariana_nav_plan
    assert plan is not None and plan.ok
    out = tmp_path_factory.mktemp("nav22")
    record = RunRecord("mariana-nav", 1, None, plan.points, np.empty((0, 3)), None, plan)
    export.write_exports(out, record, world.origin, mission.vehicle.speed, ("plan", "moos", "csv"))
    return world, mission, plan, out


def _check(path, capsys) -> tuple[int, dict]:
    code = main(["mission", "check", str(path), "--scenario", "mariana-nav", "--json"])
    return code, json.loads(capsys.readouterr().out)


def test_each_file_waits_at_its_surface_fixes_and_the_check_reads_the_plan_time_back(mariana, capsys):
    world, mission, plan, out = mariana
    fixes = np.array([k == "gps" for k in plan.kinds])
    assert fixes.sum() == 6 and mission.navigation.surface_s == 120.0
    doc = json.loads((out / "mission.plan").read_text())
    holds = [it["params"][0] for it in doc["mission"]["items"] if it["command"] == 16]
    np.testing.assert_array_equal(holds, np.where(fixes, 120, 0))  # param 1 at the surfacings only
    n = len(plan.points)
    np.testing.assert_array_equal(read_dwells(out / "mission.plan", n + 1), np.r_[0.0, plan.dwell_s])  # home first
    np.testing.assert_array_equal(moos_dwells((out / "mission.moos").read_text(), n), plan.dwell_s)
    model = EnergyModel.from_vehicle(mission.vehicle)
    planned = energy_budget(world, plan.points, model, mission.vehicle.speed, dwell=plan.dwell_s)
    for name in ("mission.moos", "mission.csv"):  # the csv carries no wait: the scenario's surface_s
        rec = _check(out / name, capsys)[1]
        assert rec["navigation"]["ok"] and rec["energy"]["energy_status"] == "EXACT", rec
        assert rec["energy"]["duration_s"] == pytest.approx(planned.duration_s, abs=0.5)
        assert rec["energy"]["energy_wh"] == pytest.approx(planned.energy_wh, rel=1e-6)
    rec = _check(out / "mission.plan", capsys)[1]  # its launch from home (a dive at the start) more
    assert rec["energy"]["energy_status"] == "EXACT", rec
    dive = rec["energy"]["leg_speeds_mps"][0]  # ArduSub's descent from home, as the check judges the file's speeds
    launch = energy_budget(world, np.vstack([[*plan.points[0, :2], 0.0], plan.points[:1]]), model, dive).duration_s
    # to 10 s in 15.7 h: the legs as ArduSub's WPNav flies the .plan's horizontal speed commands (docs/missions.md),
    # 3 s off the plan's; the waits themselves to 1 s below (with and without them)
    assert rec["energy"]["duration_s"] == pytest.approx(planned.duration_s + launch, abs=10.0)
    # the launch dives 1 500 m over home in the 0.051 m/s current without lock: D grows by |c|·T·1 %, which the plan
    # budgets too (before wave 17 it started at depth: 299.7 m planned, 300.4 m read back; test_nav23_launch.py)
    assert rec["navigation"]["ok"], rec
    assert rec["navigation"]["nav_error_max_m"] == pytest.approx(plan.check.budget.max_error_m, abs=1e-3)


def test_a_file_without_its_waits_is_budgeted_without_them(mariana, capsys, tmp_path):
    world, mission, plan, out = mariana
    doc = json.loads((out / "mission.plan").read_text())
    for it in doc["mission"]["items"]:
        if it["command"] == 16:
            it["params"][0] = 0
    bare = tmp_path / "bare.plan"
    bare.write_text(json.dumps(doc))
    waited = _check(out / "mission.plan", capsys)[1]["energy"]["duration_s"]
    code, rec = _check(bare, capsys)
    assert waited - rec["energy"]["duration_s"] == pytest.approx(plan.dwell_s.sum(), abs=1.0)
    assert code == 1 and rec["navigation"]["message"].startswith("waypoint ")  # a surfacing without a wait: no fix
    assert "less than surface_s 120 s for its GPS fix (6 surface fixes so)" in rec["navigation"]["message"]
    assert not rec["navigation"]["ok"]


def test_the_longest_hold_ardupilot_stores_is_exported_and_read_back_and_one_more_second_is_refused(tmp_path):
    from auvplan.errors import DataError
    from auvplan.io.missions.formats import to_moos, to_qgc_plan

    pts = np.array([[0.0, 0.0, -5.0], [100.0, 0.0, 0.0], [200.0, 0.0, -5.0]])
    path = tmp_path / "m.plan"
    path.write_text(json.dumps(to_qgc_plan(pts, (10.0, 10.0), 1.5, dwell=[0.0, 65534.2, 0.0])))
    np.testing.assert_array_equal(read_dwells(path, 4), [0.0, 0.0, 65535.0, 0.0])  # home first; rounded up
    with pytest.raises(DataError, match="waypoint 1 waits 65535.5 s"):
        to_qgc_plan(pts, (10.0, 10.0), 1.5, dwell=[0.0, 65535.5, 0.0])
    np.testing.assert_array_equal(moos_dwells(to_moos(pts, 1.5, dwell=[0.0, 90.5, 0.0]), 3), [0.0, 91.0, 0.0])
