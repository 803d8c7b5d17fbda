"""``run`` and ``plan`` of a glider scenario (``[vehicle] type = "glider"``): the job of :mod:`auvplan.app.glider`
and its summary line."""

from __future__ import annotations

import argparse
import json
import math
from typing import Any

__all__: list[str] = []  # handlers: CLI internals, not library API


def _h(seconds: Any) -> str:
    return f"{seconds / 3600:.2f} h" if isinstance(seconds, (int, float)) and math.isfinite(seconds) else "n/a"


def describe_glider(rec: dict[str, Any]) -> str:
    """The human summary of a glider run."""
    if "planned_duration_s" not in rec:
        return f"{rec['scenario']}: {rec['status']} — {rec.get('message', '')}"
    pct = rec["planned_vs_flown_pct"]
    saved = rec["saved_vs_steady_heading_pct"]
    return (f"{rec['scenario']}: {rec['status']} — glider, {rec['surfacings_planned']} dive cycles of "
            f"{rec['cycle_s'] / 3600:.2f} h at {rec['cycle_speed_m_s']:.3f} m/s through the water\n"
            f"  planned {_h(rec['planned_duration_s'])}, flown {_h(rec['flown_duration_s'])}"
            + (f" ({pct:.1f} % apart)" if pct is not None else "")
            + f"; nose at the goal {_h(rec['steady_heading_duration_s'])}"
            + (f" ({saved:.1f} % saved)" if saved is not None and math.isfinite(saved) else "")
            + f"\n  energy {rec['flown_energy_j'] / 3600:.1f} Wh flown ({rec['inflections']} pump strokes), "
              f"endurance {rec['endurance_days']:.0f} days")


def cmd_glider(args: argparse.Namespace) -> int:
    """``run``/``plan`` of a glider scenario: plan in dive cycles, fly, write the mission files."""
    from ..app.glider import glider_scenario

    quiet = getattr(args, "quiet", False) or getattr(args, "json", False)

    def say(text: str) -> None:
        if not quiet:
            from .output import stage

            stage(text)  # its line, then its clock in place of the command's starting clock (issue 56)

    sc, rec = glider_scenario(args.scenario, getattr(args, "out", None), getattr(args, "force", False), say)
    from .output import finish

    finish()  # the live line, before the result
    if getattr(args, "json", False):
        print(json.dumps(rec, allow_nan=False, default=str))
    else:
        print(describe_glider(rec))
        if getattr(args, "out", None):
            print(f"results in {args.out}/ (slocum/goto_l10.ma, yo10.ma, surfac10.ma; seaglider/targets)")
    return 0 if rec["status"] in ("EXACT", "APPROXIMATE") and rec.get("arrived") else 1


def glider_checks(args: argparse.Namespace, files: list[str]) -> int:
    """``mission check`` of glider files (:func:`auvplan.app.glider.check_glider_file`); exit 1 when one fails."""
    from ..app.glider import check_glider_files

    recs = check_glider_files(args.scenario, files)
    if getattr(args, "json", False):
        print(json.dumps(recs[0] if len(recs) == 1 else recs, allow_nan=False, default=str))
    else:
        for r in recs:
            flown = (f"flown in {_h(r['flown_duration_s'])}, {r['energy_wh']:.0f} of {r['battery_wh']:.0f} Wh"
                     if r["arrived"] else "not arrived")
            print(f"{r['file']} ({r['format']}, {r['waypoints']} waypoints, radius {r['radius_m']:g} m): "
                  f"{'OK' if r['ok'] else 'FAIL'} — {flown}" + (f"; {r['message']}" if r["message"] else ""))
    return 0 if all(r["ok"] for r in recs) else 1
