"""``report``, ``export`` and ``mission check``: a results folder written before re-rendered or exported
(:mod:`auvplan.app.results`), and mission files checked (:mod:`auvplan.app.check`); their output."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from .output import finish

if TYPE_CHECKING:
    from ..sim import Mission, RunRecord
    from ..world import World


__all__: list[str] = []  # handlers: CLI internals, not library API


def _load(args: argparse.Namespace) -> tuple[Path, RunRecord, str, World, Mission]:
    from ..app.results import FIGURES, load_results
    from ..io.files.safeio import RESULT_NAMES

    names = [*RESULT_NAMES, *(FIGURES if getattr(args, "figures", False) else ())] if args.command == "report" \
        else [f"mission.{f}" for f in args.format]
    return load_results(args.dir, names, force=args.force)


def cmd_report(args: argparse.Namespace) -> int:
    """``report``: report.html (and with ``--figures`` the static figures) of a results folder."""
    from ..app.results import write_report

    out, record, text, world, mission = _load(args)
    path, notes = write_report(out, world, mission, record, text, figures=args.figures, board=args.board_storage)
    finish()  # the live progress line, before the result (issue 56)
    for line in notes:  # a format that would fly a tail-first leg nose-first
        print(f"auvplan: {line}", file=sys.stderr)
    print(f"report: {path} ({path.stat().st_size / 1e6:.1f} MB)")
    return 0


def cmd_export(args: argparse.Namespace) -> int:
    """``export``: the mission files of a results folder in the formats asked for."""
    from ..app.results import planned_speeds
    from ..io.missions import export

    out, record, _, world, mission = _load(args)
    speeds = planned_speeds(out, record, mission)
    deploy = export.deploy_for(world, mission, record, speeds, export.survey_payload(out, record))  # issue 51
    # the .plan first: refused (its mission storage, a fence across ±180°), nothing is written
    fmts = sorted(args.format, key=lambda f: f != "plan")
    paths = export.write_exports(out, record, world.origin, speeds, fmts, args.full, deploy, args.board_storage)
    paths.sort(key=lambda p: list(args.format).index(p.suffix[1:]))  # printed in the order asked for
    finish()  # the live progress line, before the result (issue 56)
    for p in paths:
        print(p)
    return 0


def cmd_mission_check(args: argparse.Namespace) -> int:
    """``mission check FILE... --scenario S``: each file's verdict (or one JSON object); exit 1 when one fails."""
    import numpy as np

    from ..app.check import check_missions
    from ..io.missions.glider import is_glider_file
    from ..io.missions.readback.mission_storage import storage_line
    from ..io.results import records

    gliders = [f for f in args.files if is_glider_file(Path(f))]
    others = [f for f in args.files if f not in gliders]
    if gliders and others:  # two vehicles' checks: never one file's verdict for both (the others went unchecked)
        from ..errors import AuvplanError

        raise AuvplanError(f"mission check: {gliders[0]} is a glider file and {others[0]} is not: check glider files "
                           "and other mission files in separate runs")
    if gliders:  # issue 58: Slocum goto_lNN.ma and Seaglider targets, read back and flown by the scenario's glider
        from .glider import glider_checks

        return glider_checks(args, gliders)
    sc, checks = check_missions(args.scenario, args.files, args.pitch, args.board_storage)
    for c in checks if not args.json else ():
        name, check, vlimits = c.record["file"], c.check, c.vehicle
        fmt = c.record["format"]
        seabed = bool(np.isfinite(check.min_altitude_m))  # inf: the scenario has no seabed (nothing to clear)
        held = (f"; flown at {check.pitch_deg:g}° pitch: least altitude {check.executor_min_altitude_m:.2f} m"
                if check.semantics == "held" and seabed else "")
        altitude = (f"least altitude {check.min_altitude_m:.2f} m (required {check.required_altitude_m:g} m, leg "
                    f"{check.min_altitude_leg})" if seabed else
                    "no seabed in the scenario: altitude not checked (the sea surface, depth band and bounds were)")
        obstacles = (f"least obstacle distance {check.min_obstacle_distance_m:.2f} m (margin "
                     f"{check.obstacle_margin_m:g} m), {check.obstacle_hits} legs meet an obstacle"
                     if np.isfinite(check.min_obstacle_distance_m) else "no static obstacle in the scenario")
        limits = "".join(f"{r}; " for r in (check.limits.reasons() if check.limits is not None else []))
        print(f"{name} ({fmt}, depth {check.semantics}): {'OK' if check.ok else 'FAIL'} — {limits}{altitude}, "
              f"{obstacles}{held}")
        n = len(vlimits.violations)
        print(f"{name} vehicle: {'OK' if vlimits.ok else 'FAIL'} — {vlimits.summary}"
              + (f"; {n} violation{'' if n == 1 else 's'}: {vlimits.message}" if not vlimits.ok else ""))
        if c.speed_line:  # legs the file does not give a speed for: judged at the vehicle's
            print(f"{name}: {c.speed_line}")
        print(f"{name}: {c.energy_line}")
        print(f"{name}: {c.deploy_line}")
        if "mission_storage" in c.record["deploy"]:  # a .plan: the storage it needs, failing on --board-storage's
            print(f"{name}: {storage_line(c.record['deploy']['mission_storage'])}")
        if c.terrain_following:  # a .plan's terrain-frame legs, flown following the seabed
            print(f"{name} {c.terrain_following}")
        for line in c.navigation:  # issue 52
            print(f"{name} {line}")
        for z in c.zones:
            legs = ", ".join(str(k) for k in z.entered_legs)
            print(f"{name} zone {z.name!r}: " + (f"FAIL — entered by leg{'s' if len(z.entered_legs) > 1 else ''} "
                  f"{legs}" if z.entered_legs else f"OK — closest approach {z.closest_m:.1f} m "
                  f"(on {c.record['zones_measured_on']})"))
        if sc.mission.confidence:
            print(f"{name}: clearance {check.min_altitude_m:.2f} m at {100 * sc.mission.confidence:g} % "
                  f"(above the worst-case seabed, [terrain] uncertainty; required {check.required_altitude_m:g} m)")
    if args.json:
        recs = [c.record for c in checks]
        print(json.dumps(records.jsonable(recs[0] if len(recs) == 1 else recs)))
    return max((0 if c.ok else 1 for c in checks), default=0)
