"""``auvplan survey SCENARIO --out DIR`` (and ``run`` of a scenario with ``[survey]``): the arguments to the job
of :mod:`auvplan.app.survey`, and its summary (a human text, or one JSON object)."""

from __future__ import annotations

import argparse
import math

__all__ = ["cmd_survey"]


def _say(args: argparse.Namespace, text: str) -> None:
    if not (getattr(args, "quiet", False) or getattr(args, "json", False)):
        from .output import stage

        stage(text)  # its line, then its clock in place of the one before (never silent, issue 56)


def cmd_survey(args: argparse.Namespace) -> int:
    """Run the survey command.

    Parameters
    ----------
    args : argparse.Namespace
        ``scenario``, ``out``, ``seed``, ``guidance``, ``full``, ``force``, ``json``, ``quiet``, ``board_storage``.

    Returns
    -------
    int
        0 when the survey was planned and flown, 1 when a check, a transit or the flight failed.
    """
    from ..app.survey import survey_scenario
    from .output import runner_of

    sc, rec = survey_scenario(args.scenario, args.out, args.force, args.seed, getattr(args, "guidance", None),
                              args.full, lambda text: _say(args, text), runner_of(args), args.board_storage)
    m = rec["lawnmower"]
    gaps = rec["flown"]["gaps"] if rec["flown"] else 0
    human = (f"{sc.name}: {rec['status']} — {rec['lines']} lines at {rec['heading_deg']:.0f}°, "
             f"planned coverage {rec['planned']['coverage_pct']:.2f} % (overlap {rec['planned']['overlap_min_pct']:.1f}"
             f"–{rec['planned']['overlap_max_pct']:.1f} %)"
             + (f", flown {rec['coverage_pct']:.2f} % (overlap {rec['overlap_min_pct']:.1f}–"
                f"{rec['overlap_max_pct']:.1f} %, {gaps} gap{'' if gaps == 1 else 's'})" if rec["flown"] else "")
             + f"\n  survey {rec['survey_length_m'] / 1e3:.1f} km"
             + (f" in {rec['survey_time_s'] / 3600:.2f} h" if math.isfinite(rec["survey_time_s"]) else "")
             + _versus_lawnmower(m)
             + (f"\n  {rec['nav_spacing']['text']}" if rec.get("nav_spacing") else "")
             + (f"\n  {rec['message']}" if rec["message"] else "")
             + "".join(f"\n  note: {n}" for n in rec.get("notes", [])))
    from .output import finish

    finish()  # the live progress line, before the result (issue 56)
    if args.json:
        print(_json(rec))
    else:
        print(human)
        if args.out:
            print(f"results in {args.out}/")
    return 0 if rec["status"] in ("EXACT", "APPROXIMATE") else 1


def _versus_lawnmower(m: dict[str, float]) -> str:
    """The comparison with the fixed lawnmower, where the survey saves something; else what the lawnmower flies
    (a corridor as wide as two swaths is two lines either way: a "saving" of minus the bends' length)."""
    head = f"; fixed lawnmower for {m['shallowest_m']:.0f} m: {m['lines']:.0f} lines"
    if m["lines_saved"] > 0 or m["line_length_saved_m"] > 0.0:
        return head + f", {m['lines_saved']:.0f} lines and {m['line_length_saved_m'] / 1e3:.1f} km of line saved"
    return head + f", {m['line_length_m'] / 1e3:.1f} km: the depth-adaptive spacing saves no line here"


def _json(rec: dict[str, object]) -> str:
    import json

    from ..io.results import records

    return json.dumps(records.jsonable(rec))
