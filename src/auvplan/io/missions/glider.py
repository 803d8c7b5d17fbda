"""Glider mission files as pilots load them: Slocum ``.ma`` behaviour files and the Seaglider ``targets`` file.

**Slocum** (Teledyne Webb Research, *Slocum G2 Glider Operators Manual*, "Mission and behaviour
files"; the ``beh_args.h`` enumerations quoted in the stock ``mafiles``, e.g. ``yo10.ma`` and
``surfac03.ma`` of a Slocum release, and the ``goto_l10.ma`` written by Rutgers' Glider Guidance
System).  A ``.ma`` file starts with ``behavior_name=NAME``; ``#`` starts a comment; behaviour
arguments sit between ``<start:b_arg>`` and ``<end:b_arg>``, one per line as
``b_arg: NAME(UNIT) VALUE``; a ``goto_list`` carries its waypoints between ``<start:waypoints>`` and
``<end:waypoints>``, one per line as ``LON LAT`` in the glider's DDMM.MMMM notation (degrees × 100
+ minutes, negative west and south; longitude first).  Written here:

* ``goto_lNN.ma`` (``behavior_name=goto_list``): the surfacing waypoints, ``list_stop_when`` 7
  (``BAW_WHEN_WPT_DIST``) with ``list_when_wpt_dist`` the capture radius, ``initial_wpt`` 0,
  ``num_legs_to_run`` the number of waypoints (stop at the last);
* ``yoNN.ma`` (``behavior_name=yo``): ``d_target_depth``, ``d_target_altitude`` (``min_altitude``),
  ``c_target_depth`` (``climb_depth_m``), ``d_/c_use_pitch`` 3 (servo) with ``d_/c_pitch_value`` in
  radians, ``num_half_cycles_to_do`` = 2 × the yos of a planned cycle (``yos``, or with ``surface_every_s``
  up to the first top at or after it, the first dive from the surface included: the one rule of the planner,
  the flight and these files, :func:`auvplan.vehicles.glider.yos_per_cycle`) and
  ``end_action`` 2 (resume: after the surfacing the yo starts again);
* ``surfacNN.ma`` (``behavior_name=surface``): ``start_when`` 2 (``BAW_PITCH_IDLE``: when the yo has done its
  half cycles, at the top of the last climb), ``end_action`` 2 (resume), ``gps_wait_time`` ``surface_time_s``:
  every planned surfacing; with ``surface_every_s`` a second one, ``start_when`` 12 (``BAW_NOCOMM_SECS``: when
  there has been no comms for ``when_secs``, wherever the glider is) as a safety net only, ``when_secs`` = the
  cycle's planned time underwater × (yos + 1) / yos (one yo more, with its share of the first dive and the last
  climb), so that a nominal cycle never reaches it.  (It was ``surface_every_s``: the time elapses before the
  first top after it, so every cycle was cut short mid-dive and the glider came up from depth, not where or when
  the plan surfaced.)

**Seaglider** (University of Washington APL, *Seaglider File Formats Manual* v66, "targets"; the
same syntax as the targets files of NOAA's ``agate`` toolbox, ``makeTargetsFile.m``): ``/`` starts a
comment line; each target is one line ``NAME lat=DDMM.MMMM lon=DDDMM.MMMM radius=R goto=NEXT``
(signed DDMM like Slocum's; the last target's ``goto`` is itself, so the glider holds there).
"""

from __future__ import annotations

import contextlib
import math
import os
import re
from pathlib import Path
from typing import Any

import numpy as np

from ...errors import DataError
from ..data.geo import LocalFrame

__all__ = ["to_ddmm", "from_ddmm", "slocum_files", "write_slocum", "seaglider_targets", "read_goto", "read_ma",
           "read_targets", "GLIDER_SUFFIXES", "is_glider_file", "read_glider_waypoints"]

#: Files :func:`read_glider_waypoints` reads (``mission check``).
GLIDER_SUFFIXES = (".ma",)


def to_ddmm(deg: float) -> float:
    """Decimal degrees as the gliders' signed DDMM.MMMM (degrees × 100 + minutes).

    Parameters
    ----------
    deg : float
        Degrees (negative west/south).

    Returns
    -------
    float
        DDMM.MMMM with the sign of ``deg``.
    """
    a = abs(deg)
    d = math.floor(a)
    m = (a - d) * 60.0
    if round(m, 4) >= 60.0:
        d, m = d + 1, 0.0
    return math.copysign(d * 100.0 + m, deg)


def from_ddmm(value: float) -> float:
    """Signed DDMM.MMMM back to decimal degrees.

    Parameters
    ----------
    value : float
        DDMM.MMMM.

    Returns
    -------
    float
        Degrees.
    """
    a = abs(value)
    d = math.floor(a / 100.0)
    return math.copysign(d + (a - 100.0 * d) / 60.0, value)


def _latlon(points: Any, origin: tuple[float, float]) -> list[tuple[float, float]]:
    p = np.asarray(points, dtype=float)
    lon, lat = LocalFrame(*origin).inverse(p[:, 0], p[:, 1])
    return [(float(a), float(o)) for a, o in zip(lat, lon, strict=True)]


def _b_args(args: list[tuple[str, Any, str]]) -> list[str]:
    return ["<start:b_arg>", *(f"    b_arg: {k} {v}" + (f"    # {c}" if c else "") for k, v, c in args),
            "<end:b_arg>"]


def slocum_files(points: Any, origin: tuple[float, float], glider: Any, min_altitude: float,
                 number: int = 10, name: str = "auvplan", *, yos: int | None = None,
                 underwater_s: float | None = None) -> dict[str, str]:
    """The Slocum behaviour files of a glider mission (module notes).

    Parameters
    ----------
    points : array_like, shape (M, 2+)
        The surfacing waypoints in the local frame (m); the last is the goal.
    origin : (lat, lon)
        The frame's origin (degrees).
    glider : GliderParams
        Yo depths, pitch, yos per surfacing, surfacing time, capture radius.
    min_altitude : float
        Least altitude above the seabed at the bottom of a dive (m).
    number : int, default 10
        The files' number NN (``goto_lNN.ma``, ``yoNN.ma``, ``surfacNN.ma``; 10-99).
    name : str, default "auvplan"
        Mission name for the comments.
    yos : int, optional
        Yos between two surfacings as planned (:attr:`auvplan.planners.timeopt.glider.Cycle.yos`, by
        :func:`auvplan.vehicles.glider.yos_per_cycle`; default ``glider.yos``, the count when ``surface_every_s``
        is 0).  Required with ``surface_every_s``.
    underwater_s : float, optional
        A planned cycle's time underwater (s; :attr:`~auvplan.planners.timeopt.glider.Cycle.underwater_s`):
        the no-comms safety net's ``when_secs`` is that × (yos + 1) / yos.  Required with ``surface_every_s``.

    Returns
    -------
    dict
        File name → text.
    """
    yos = _cycle_yos(glider, number, yos, underwater_s)
    pitch = math.radians(glider.pitch_deg)
    out = {f"goto_l{number}.ma": _goto_file(_latlon(points, origin), glider, number, name),
           f"yo{number}.ma": _yo_file(glider, min_altitude, number, name, yos, pitch),
           f"surfac{number}.ma": _surface_file(glider, number, name, yos, pitch)}
    if glider.surface_every_s > 0:
        assert underwater_s is not None
        out[f"surfac{number + 1}.ma"] = _nocomm_file(glider, number, name, yos, underwater_s, pitch)
    return out


def _cycle_yos(glider: Any, number: int, yos: int | None, underwater_s: float | None) -> int:
    """The yos of a planned cycle the files are written for, the arguments checked (:func:`slocum_files`)."""
    if not 10 <= number <= 98:
        raise ValueError(f"number = {number}: Slocum behaviour files are numbered 10-99")
    if glider.surface_every_s > 0 and not (underwater_s is not None and underwater_s > 0):
        raise ValueError("surface_every_s is set: the no-comms surfacing needs the planned cycle's underwater_s "
                         "(a cycle's time underwater), else it would fire mid-dive")
    if glider.surface_every_s > 0 and yos is None:
        raise ValueError("surface_every_s is set: yoNN.ma needs the planned cycle's yos (Cycle.yos, the first top at "
                         "or after surface_every_s), not glider.yos")
    yos = glider.yos if yos is None else int(yos)
    if yos < 1:
        raise ValueError(f"yos = {yos}: a cycle has at least one yo")
    return yos


def _goto_file(pts: list[tuple[float, float]], glider: Any, number: int, name: str) -> str:
    """``goto_lNN.ma``: the surfacing waypoints ``(lat, lon)``, run once, each reached within the capture radius."""
    goto = ["behavior_name=goto_list", f"# goto_l{number}.ma: {name}, {len(pts)} surfacing waypoints written by "
            "auvplan (planned in dive cycles against the depth-averaged current)",
            *_b_args([("num_legs_to_run(nodim)", len(pts), "run the list once, stop at the last"),
                      ("start_when(enum)", 0, "BAW_IMMEDIATELY"),
                      ("list_stop_when(enum)", 7, "BAW_WHEN_WPT_DIST"),
                      ("list_when_wpt_dist(m)", f"{glider.capture_radius_m:.0f}", "capture radius"),
                      ("initial_wpt(enum)", 0, "start with the first"),
                      ("num_waypoints(nodim)", len(pts), "")]),
            "<start:waypoints>", "#   LON (DDDMM.MMMM)  LAT (DDMM.MMMM)",
            *(f"    {to_ddmm(lon):.4f}    {to_ddmm(lat):.4f}    # {k + 1}" for k, (lat, lon) in enumerate(pts)),
            "<end:waypoints>"]
    return "\n".join(goto) + "\n"


def _yo_file(glider: Any, min_altitude: float, number: int, name: str, yos: int, pitch: float) -> str:
    """``yoNN.ma``: ``yos`` dives and climbs between two surfacings, at ``pitch`` (rad)."""
    yo = ["behavior_name=yo", f"# yo{number}.ma: {name}, climb {glider.climb_depth_m:g} m, dive "
          f"{glider.dive_depth_m:g} m, altitude {min_altitude:g} m, pitch {glider.pitch_deg:g} deg, "
          f"{yos} yos per surfacing",
          *_b_args([("start_when(enum)", 2, "BAW_PITCH_IDLE"),
                    ("num_half_cycles_to_do(nodim)", 2 * yos, "dives + climbs between surfacings"),
                    ("d_target_depth(m)", f"{glider.dive_depth_m:g}", ""),
                    ("d_target_altitude(m)", f"{min_altitude:g}", ""),
                    ("d_use_pitch(enum)", 3, "servo"),
                    ("d_pitch_value(X)", f"{-pitch:.4f}", f"-{glider.pitch_deg:g} deg"),
                    ("c_target_depth(m)", f"{glider.climb_depth_m:g}", ""),
                    ("c_target_altitude(m)", -1, "off"),
                    ("c_use_pitch(enum)", 3, "servo"),
                    ("c_pitch_value(X)", f"{pitch:.4f}", f"{glider.pitch_deg:g} deg"),
                    ("end_action(enum)", 2, "resume")])]
    return "\n".join(yo) + "\n"


def _surface_file(glider: Any, number: int, name: str, yos: int, pitch: float) -> str:
    """``surfacNN.ma``: every planned surfacing, at the top of the yo's last climb."""
    surf = ["behavior_name=surface", f"# surfac{number}.ma: {name}, surface when the yo has done its "
            f"{yos} yos",
            *_b_args([("start_when(enum)", 2, "BAW_PITCH_IDLE"),
                      ("end_action(enum)", 2, "resume"),
                      ("gps_wait_time(s)", f"{glider.surface_time_s:.0f}", ""),
                      ("c_use_pitch(enum)", 3, "servo"),
                      ("c_pitch_value(X)", f"{pitch:.4f}", "")])]
    return "\n".join(surf) + "\n"


def _nocomm_file(glider: Any, number: int, name: str, yos: int, underwater_s: float, pitch: float) -> str:
    """``surfac(NN+1).ma``: the no-comms safety net, a planned cycle and one yo more underwater (module notes)."""
    secs = math.ceil(underwater_s * (yos + 1) / yos)  # a cycle and one yo more: never in a nominal cycle
    every = ["behavior_name=surface", f"# surfac{number + 1}.ma: {name}, safety net: surface after {secs} s "
             f"without comms (a planned cycle is {underwater_s:.0f} s underwater; surfac{number} surfaces it)",
             *_b_args([("start_when(enum)", 12, "BAW_NOCOMM_SECS"),
                       ("when_secs(sec)", f"{secs}", "the cycle's time underwater and one yo"),
                       ("end_action(enum)", 2, "resume"),
                       ("gps_wait_time(s)", f"{glider.surface_time_s:.0f}", ""),
                       ("c_use_pitch(enum)", 3, "servo"),
                       ("c_pitch_value(X)", f"{pitch:.4f}", "")])]
    return "\n".join(every) + "\n"


def write_slocum(folder: Path, points: Any, origin: tuple[float, float], glider: Any, min_altitude: float,
                 number: int = 10, *, yos: int | None = None, underwater_s: float | None = None) -> list[Path]:
    """Write :func:`slocum_files` into ``folder``: all of them or none, each atomically, never over an existing file.

    Each file goes through :func:`auvplan.io.files.safeio.write_new` (a temporary file, flushed, renamed into
    place): a crash mid-write leaves no torn file beside the pilot's own, and a failure after the first file
    removes the files this call wrote.

    Parameters
    ----------
    folder : Path
        Destination folder (created).
    points : array_like, shape (M, 2+)
        The surfacing waypoints (m), as :func:`slocum_files`.
    origin : (lat, lon)
        The frame's origin (degrees).
    glider : GliderParams
        The glider.
    min_altitude : float
        Least altitude above the seabed (m).
    number : int, default 10
        The files' number NN.
    yos, underwater_s : int, float, optional
        The planned cycle, as :func:`slocum_files`.

    Returns
    -------
    list of Path
        The files written.
    """
    from ..files.safeio import write_new

    folder.mkdir(parents=True, exist_ok=True)
    files = slocum_files(points, origin, glider, min_altitude, number, yos=yos, underwater_s=underwater_s)
    taken = [n for n in files if os.path.lexists(folder / n)]
    if taken:
        raise DataError(f"{folder / taken[0]}: exists; auvplan never overwrites a mission file")
    out: list[Path] = []
    try:
        for n, text in files.items():
            out.append(write_new(folder / n, text))
    except BaseException:
        for p in out:  # all or none: a goto list without its yo and surface files is not a mission
            with contextlib.suppress(OSError):
                p.unlink()
        raise
    return out


def seaglider_targets(points: Any, origin: tuple[float, float], radius: float, name: str = "auvplan") -> str:
    """The Seaglider ``targets`` file of the surfacing waypoints (module notes).

    Parameters
    ----------
    points : array_like, shape (M, 2+)
        Waypoints in the local frame (m); the last is the goal.
    origin : (lat, lon)
        The frame's origin (degrees).
    radius : float
        Target radius (m).
    name : str, default "auvplan"
        Mission name for the comment.

    Returns
    -------
    str
        The file's text; targets ``WP01`` … and ``GOAL``.
    """
    pts = _latlon(points, origin)
    names = [f"WP{k + 1:02d}" for k in range(len(pts) - 1)] + ["GOAL"]
    lines = [f"/ targets: {name}, {len(pts)} targets written by auvplan",
             "/ NAME lat=DDMM.MMMM lon=DDDMM.MMMM radius=M goto=NEXT"]
    for k, (lat, lon) in enumerate(pts):
        nxt = names[min(k + 1, len(pts) - 1)]
        lines.append(f"{names[k]} lat={to_ddmm(lat):.4f} lon={to_ddmm(lon):.4f} radius={radius:.0f} goto={nxt}")
    return "\n".join(lines) + "\n"


def read_ma(text: str) -> tuple[str, dict[str, float]]:
    """A Slocum ``.ma`` file's behaviour name and its ``b_arg`` values by name (units dropped).

    Parameters
    ----------
    text : str
        The file's text.

    Returns
    -------
    (str, dict)
        ``behavior_name`` and ``{arg: value}``.
    """
    name, args = "", {}
    for raw in text.splitlines():
        line = raw.split("#", 1)[0].strip()
        if line.startswith("behavior_name="):
            name = line.split("=", 1)[1].strip()
        m = re.match(r"b_arg:\s*([A-Za-z_0-9]+)\([^)]*\)\s+(\S+)", line)
        if m:
            args[m.group(1)] = float(m.group(2))
    return name, args


def read_goto(text: str) -> list[tuple[float, float]]:
    """A ``goto_list`` file's waypoints as (lat, lon) degrees.

    Parameters
    ----------
    text : str
        The file's text.

    Returns
    -------
    list of (float, float)
        The waypoints in order.
    """
    body = text.split("<start:waypoints>", 1)[1].split("<end:waypoints>", 1)[0]
    out = []
    for raw in body.splitlines():
        line = raw.split("#", 1)[0].split()
        if len(line) >= 2:
            out.append((from_ddmm(float(line[1])), from_ddmm(float(line[0]))))
    return out


def read_targets(text: str) -> list[dict[str, Any]]:
    """A Seaglider ``targets`` file's targets.

    Parameters
    ----------
    text : str
        The file's text.

    Returns
    -------
    list of dict
        ``name``, ``lat``, ``lon`` (degrees), ``radius`` (m), ``goto``, in file order.
    """
    out = []
    for raw in text.splitlines():
        line = raw.strip()
        if not line or line.startswith("/"):
            continue
        head, *rest = line.split()
        kv = dict(item.split("=", 1) for item in rest if "=" in item)
        out.append({"name": head, "lat": from_ddmm(float(kv["lat"])), "lon": from_ddmm(float(kv["lon"])),
                    "radius": float(kv["radius"]), "goto": kv["goto"]})
    return out


def is_glider_file(path: Path) -> bool:
    """Whether ``mission check`` reads ``path`` as a glider file: a Slocum ``goto_l*.ma`` or a Seaglider ``targets``.

    Parameters
    ----------
    path : Path
        The file.

    Returns
    -------
    bool
        By its name (a ``targets…`` name with a mission format's suffix, ``targets.csv``, is that format).
    """
    from .readback.readers import MISSION_SUFFIXES  # a "targets_v2.csv" is a CSV mission, not a Seaglider targets file

    return (path.suffix == ".ma" and path.name.startswith("goto_l")) or (
        path.name.startswith("targets") and path.suffix.lower() not in MISSION_SUFFIXES)


def read_glider_waypoints(path: Path, origin: tuple[float, float]) -> tuple[np.ndarray, float, str]:
    """A glider file's waypoints in the local frame, its capture radius and its format.

    Parameters
    ----------
    path : Path
        ``goto_lNN.ma`` or ``targets``.
    origin : (lat, lon)
        The scenario's origin (degrees).

    Returns
    -------
    (ndarray (M, 2), float, str)
        Waypoints (m), radius (m), ``"slocum"`` or ``"seaglider"``.

    Raises
    ------
    DataError
        When the file does not parse (the message names the file).
    """
    text = path.read_text()
    try:
        if path.suffix == ".ma":
            latlon = read_goto(text)
            radius = read_ma(text)[1].get("list_when_wpt_dist", math.nan)
            fmt = "slocum"
        else:
            tg = read_targets(text)
            latlon = [(t["lat"], t["lon"]) for t in tg]
            radius = tg[-1]["radius"] if tg else math.nan
            fmt = "seaglider"
    except (IndexError, KeyError, ValueError) as exc:
        raise DataError(f"{path}: not a glider mission file ({exc})") from exc
    if not latlon:
        raise DataError(f"{path}: no waypoints")
    lat, lon = np.array(latlon).T
    x, y = LocalFrame(*origin).forward(lon, lat)
    return np.stack([x, y], axis=1), float(radius), fmt
