"""A run's own export passes its own check on pitch when a surfacing's dive meets the route beside a waypoint
(helper export2, wave 17).

``mariana-nav`` launched at the surface (its start depth set to 0): :func:`auvplan.nav.apply_fixes` split the route
where the dive from a fix met it, 0.24 m past a route waypoint (leg 470, x 166000 y 74375, 1 431 m deep): a 0.255 m
leg at 19.98°, below the 2.5 m :data:`~auvplan.path.legs.FITTED_LEG_M` rule, which the 1 mm rounding of ``.csv`` and
``.moos`` read as 20.14°: ``mission check`` failed the run's own export on pitch (and leg 193: 1.76 m).  Now the
split is merged into its neighbour (a kink of the envelope: the chord is shallower and no steeper).

Oracle: ``mission check`` of the three files as written (their rounded coordinates), against the scenario's
``max_pitch_deg``; every leg of the mission at least ``FITTED_LEG_M``.
"""

from __future__ import annotations

import json
from importlib import resources

import numpy as np
import pytest

from auvplan.cli import main
from auvplan.io.missions import export
from auvplan.io.scenario import loader as sc
from auvplan.path.legs import FITTED_LEG_M
from auvplan.sim.navigation import navigation_plan
from auvplan.sim.pipeline import planned_route
from auvplan.sim.result import RunRecord


@pytest.fixture(scope="module")
def surface_launch(tmp_path_factory):
    d = tmp_path_factory.mktemp("export2")
    text = (resources.files("auvplan") / "data" / "scenarios" / "mariana-nav.toml").read_text()
    text = text.replace("start = [155000.0, 42000.0, -1500.0]", "start = [155000.0, 42000.0, 0.0]")
    text = text.replace("  [155000.0, 42000.0, -1500.0],", "  [155000.0, 42000.0, 0.0],")
    assert text.count("42000.0, 0.0]") == 2
    path = d / "mariana-surface.toml"
    path.write_text(text)
    world, mission = sc.build(sc.load(str(path)))
    _, route = planned_route(world, mission, 1)
    nav = navigation_plan(world, mission, route)
    assert nav is not None and nav.ok
    record = RunRecord(mission.name or "t", 1, None, nav.points, np.empty((0, 3)), None, nav=nav)
    deploy = export.deploy_for(world, mission, record, mission.vehicle.speed)  # the envelope, as `run` writes it
    export.write_exports(d, record, world.origin, mission.vehicle.speed, ("plan", "moos", "csv"), deploy=deploy)
    return path, d, nav


def test_no_leg_of_the_mission_is_shorter_than_the_rule(surface_launch):
    _, _, nav = surface_launch
    legs = np.linalg.norm(np.diff(nav.points, axis=0), axis=1)
    assert legs.min() >= FITTED_LEG_M, (int(legs.argmin()), float(legs.min()))


@pytest.mark.parametrize("fmt", ["plan", "moos", "csv"])
def test_the_surface_launch_export_passes_its_own_check(surface_launch, fmt, capsys):
    path, d, _ = surface_launch
    capsys.readouterr()
    code = main(["mission", "check", str(d / f"mission.{fmt}"), "--scenario", str(path), "--json"])
    rec = json.loads(capsys.readouterr().out)
    rec = rec["files"][0] if "files" in rec else rec
    assert code == 0, {k: v for k, v in rec.items() if isinstance(v, dict) and not v.get("ok", True)}
    assert rec["navigation"]["ok"], rec["navigation"]["message"]
