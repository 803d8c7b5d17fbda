"""``scenarios``, ``validate``, ``data inspect`` and ``scenario new|schema``: what is there, and is this file
right — read and printed; and ``kernels build`` (the kernels compiled ahead of time, issue 56)."""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path
from typing import Any

__all__: list[str] = []  # handlers: CLI internals, not library API


def cmd_scenarios(args: argparse.Namespace) -> int:
    """``scenarios``: the built-in scenarios with their one-line descriptions."""
    from ..io.scenario.builtins import builtin_scenarios

    for name, desc in builtin_scenarios().items():
        print(f"{name:18s} {desc}")
    return 0


def cmd_data_inspect(args: argparse.Namespace) -> int:
    """``data inspect FILE``: the layout, variables, units and axes auvplan detects."""
    from ..io.data.inspect import inspect_file

    print(inspect_file(args.file))
    return 0


def cmd_validate(args: argparse.Namespace) -> int:
    """``validate SCENARIO``: every check ``plan`` and ``run`` make before their work, and a summary."""
    from ..io.scenario import loader as scenario_io
    from ..io.scenario.inputs.members import scenario_members
    from ..sim import planning_problem

    sc = scenario_io.load(args.scenario)
    world, mission = scenario_io.build(sc)  # every check `plan` and `run` make before their work
    planning_problem(world, mission)
    members = scenario_members(sc, world)  # [currents] members: every one read and checked
    b = world.bounds
    from ..io.scenario.defaults import energy_defaults

    lines = [f"  bounds x [{b.xmin:.0f}, {b.xmax:.0f}] y [{b.ymin:.0f}, {b.ymax:.0f}] z [{b.zmin:.0f}, {b.zmax:.0f}] m"]
    if world.terrain is not None:
        t = world.terrain
        lines.append(f"  terrain {t.name}: {t.x.size} x {t.y.size} nodes, cell {t.dx:.0f} m, "
                     f"seabed {t.z.min():.0f} .. {t.z.max():.0f} m")
        if t.fit is not None:
            lines.append(f"  {t.fit.describe()}")
    def at(p: Any) -> str:  # a point derived from degrees read to the centimetre, not to 1e-12 m
        return "[" + ", ".join(f"{float(v) + 0.0:.2f}" for v in p) + "]"

    lines.append(f"  start {at(mission.start)} goal {at(mission.goal)} m; "
                 f"{len(world.obstacles)} static and {len(world.moving)} moving obstacles")
    if world.zones:
        lines.append(_zones_line(world.zones.zones))
    if members:
        lines.append(f"  {len(members)} current members: {', '.join(n for n, _ in members[:8])}"
                     + (" ..." if len(members) > 8 else "") + f"; [planner] robust = {mission.planner.robust!r}")
    if sc.mission.confidence:
        lines.append(f"  seabed: the worst case at {100 * sc.mission.confidence:g} % ([terrain] uncertainty)")
    if sc.survey is not None:
        from ..io.results.survey import survey_params

        area = survey_params(sc.survey, world, mission.vehicle, sc.base_dir, f"{sc.source}: [survey]").area
        lines.append(f"  {'corridor' if sc.survey.corridor else 'survey'} of {area.area / 1e6:.3g} km² with a "
                     f"{sc.survey.sensor} ({sc.survey.mounting} mounting)"
                     + (f", {sc.survey.tie_lines} tie lines" if sc.survey.tie_lines else ""))
    lines += [f"  note: {d}" for d in energy_defaults(sc)]
    # issue 51: OK only once every check above has passed (an error is exit 2 with nothing printed on stdout)
    print("\n".join([f"{sc.source}: OK — {sc.name}", *lines]))
    return 0


def _zones_line(zones: tuple[Any, ...]) -> str:
    """``validate``'s line on the charted zones: how many, their names and depth bands (the first few)."""
    def band(z: Any) -> str:
        if z.above_seabed is not None:
            return f"{z.above_seabed:g} m above the seabed"
        low = "the seabed" if math.isinf(z.bottom) else f"{z.bottom:g} m"
        return f"{'the surface' if z.top == 0 else f'{z.top:g} m'} to {low}"

    shown = "; ".join(f"{z.name!r} ({band(z)})" for z in zones[:4])
    return f"  {len(zones)} charted zone{'s' if len(zones) != 1 else ''} kept out of: {shown}" + \
        (f"; ... ({len(zones) - 4} more)" if len(zones) > 4 else "")


def cmd_scenario_new(args: argparse.Namespace) -> int:
    """``scenario new [FILE]``: a commented scenario template (to FILE, or stdout)."""
    from ..io.files.safeio import write_new
    from ..io.scenario.schema import template

    text = template(Path(args.file).stem if args.file else "my-mission")
    if not args.file:
        sys.stdout.write(text)
        return 0
    path = write_new(Path(args.file), text, force=args.force)
    print(f"wrote {path}; check it with: auvplan validate {path}", file=sys.stderr)
    return 0


def cmd_scenario_schema(args: argparse.Namespace) -> int:
    """``scenario schema``: the scenario format's versioned JSON Schema."""
    from ..io.scenario.schema import scenario_schema

    sys.stdout.write(json.dumps(scenario_schema(), indent=2) + "\n")
    return 0


def cmd_kernels_build(args: argparse.Namespace) -> int:
    """``kernels build [SCENARIO ...]``: plan each SCENARIO (a process each: its kernels compiled into numba's cache),
    then compile every kernel signature numba's cache holds for the current sources into one extension module
    (:mod:`auvplan.runtime.aotbuild`).  A build that cannot be done is one line on stderr and exit 1: the kernels
    then run through numba, as before."""
    import subprocess

    from ..runtime.aotbuild import BuildError, build

    for name in args.scenarios:
        done = subprocess.run([sys.executable, "-m", "auvplan", "-q", "plan", name, "--json"],
                              stdout=subprocess.DEVNULL, check=False)
        if done.returncode == 2:  # its one line is on stderr already
            return 2
    try:
        built = build()
    except BuildError as exc:
        print(f"auvplan: kernels not compiled ahead of time ({exc}); they run through numba as before",
              file=sys.stderr)
        return 1
    done_how = "up to date" if built.seconds == 0 else f"built in {built.seconds:.0f} s"
    line = f"kernels: {built.signatures} signatures of {built.kernels} kernels in {built.path} ({done_how})"
    print(line + (f"; {built.skipped} left to numba (types it binds at run time)" if built.skipped else ""))
    return 0
