"""Results folders of the command line: what makes one self-contained (the scenario text, its terrain), its
report and exports, and ``report``/``export`` of a folder written before."""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import AuvplanError
from ..io.safeio import RESULT_NAMES, atomic_write, prepare_out, save_figure

if TYPE_CHECKING:
    from ..endurance import Endurance
    from ..io.scenario.specs import Scenario
    from ..planners import PlanResult
    from ..sim import Mission, RunRecord
    from ..world import World

__all__: list[str] = ["FIGURES"]  # handlers: CLI internals, not library API


def scenario_text(sc: Scenario) -> str:
    """The text of the scenario file (empty where it cannot be read)."""
    try:
        return Path(sc.source).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return ""


def save_context(out: Path, sc: Scenario, world: World) -> None:
    """What makes a results folder self-contained: the scenario's origin and the terrain it used."""
    from ..io.results import folder as results
    from ..io.results import records

    records.write_json(out / "source.json", {"scenario_source": str(Path(sc.source).resolve())})
    results.save_terrain(out, world.terrain)


def save_plan(out: Path, sc: Scenario, world: World, result: PlanResult, seed: int,
              ensemble: dict[str, Any] | None = None) -> None:
    """``plan --out``: the plan files plus a run record without a flight, so report/export work on it."""
    from ..io.results import records
    from ..sim import RunRecord

    text = scenario_text(sc)
    empty = result.path[:0].reshape(0, 3)
    records.write_run(out, RunRecord(sc.name, seed, result, empty, empty, None), text, origin=world.origin)
    save_context(out, sc, world)
    from .ensemble import write_ensemble

    write_ensemble(out, ensemble or {})


def write_report(out: Path, world: World, mission: Mission, record: RunRecord, text: str, figures: bool = False,
                  full: bool = False, endurance: Endurance | None = None) -> Path:
    """report.html (and the exports, and with ``figures`` the static PNG/SVG figures) into ``out``."""
    from ..io.data.geo import LocalFrame
    from ..io.missions import export
    from ..io.results import records
    from ..viz.report import build_report

    frame = LocalFrame(*world.origin) if world.origin is not None else None
    formats, notes = export.exportable(record, [f for f in export.EXPORT_FORMATS
                                                if frame is not None or f not in export.GEOGRAPHIC])
    for line in notes:  # a format that would fly a tail-first leg nose-first
        print(f"auvplan: {line}", file=sys.stderr)
    from ..io.missions.energy import mission_endurance

    export.write_exports(out, record, world.origin, planned_speeds(out, record, mission), formats, full)
    if endurance is None:
        endurance = mission_endurance(world, mission, record)
    metrics = records.summary_metrics(record)
    if world.terrain is not None and world.terrain.fit is not None:
        metrics.update(records.fit_metrics(world.terrain.fit))
    from .ensemble import read_ensemble

    page = build_report(world, record, text, metrics, frame.inverse if frame else None, endurance, read_ensemble(out))
    path = atomic_write(out / "report.html", page)
    if figures:
        from ..viz import plots

        plots.write_mission_figures(out / "figures", world, record, save=save_figure,
                                    to_lonlat=frame.inverse if frame else None)
    return path


def planned_speeds(out: Path, record: RunRecord, mission: Mission) -> float | np.ndarray:
    """The speed of each leg of the mission (``legs.csv`` of the folder), else the vehicle's speed."""
    from ..io.missions.energy import read_leg_speeds

    speeds = read_leg_speeds(out, max(record.route.shape[0] - 1, 0))
    return mission.vehicle.speed if speeds is None else speeds


FIGURES = tuple(f"figures/{n}.{f}" for n in ("plan_view", "profiles", "convergence") for f in ("png", "svg"))
"""Files of ``report --figures``."""


def load_results(args: argparse.Namespace) -> tuple[Path, RunRecord, str, World, Mission]:
    """A results folder of ``report``/``export``: its record, scenario text and the World and Mission rebuilt."""
    from ..io.results import folder as results
    from ..io.results import records
    from ..io.scenario import loader as scenario_io
    from ..sim import mission_route

    out = Path(args.dir)
    if not out.is_dir():
        raise AuvplanError(f"{out}: no such results folder")
    names = [*RESULT_NAMES, *(FIGURES if getattr(args, "figures", False) else ())] if args.command == "report" \
        else [f"mission.{f}" for f in args.format]
    prepare_out(out, names, force=args.force)
    record, text = records.read_run(out)
    if not text:
        raise AuvplanError(f"{out}/scenario.toml: missing — the report needs the scenario to rebuild the world")
    sc = scenario_io.loads(text, str(out / "scenario.toml"), base_dir=results.scenario_base(out))
    world, mission = scenario_io.build(sc, terrain=results.load_terrain(out))
    if not record.route.size and record.plan is not None and record.plan.path.size:
        # a plan without a flight: export the executable mission, not the raw planned curve
        record = replace(record, route=mission_route(world, mission, record.plan.path))
    return out, record, text, world, mission


def cmd_report(args: argparse.Namespace) -> int:
    """``report``: report.html (and with ``--figures`` the static figures) of a results folder."""
    out, record, text, world, mission = load_results(args)
    path = write_report(out, world, mission, record, text, figures=args.figures)
    print(f"report: {path} ({path.stat().st_size / 1e6:.1f} MB)")
    return 0


def cmd_export(args: argparse.Namespace) -> int:
    """``export``: the mission files of a results folder in the formats asked for."""
    from ..io.missions import export

    out, record, _, world, mission = load_results(args)
    for p in export.write_exports(out, record, world.origin, planned_speeds(out, record, mission), args.format,
                                  args.full):
        print(p)
    return 0
