"""Scenario files: TOML → frozen dataclasses → :class:`World` + :class:`Mission`.

Every table maps onto one frozen dataclass (see :mod:`auvplan.io.scenario.tables`):
unknown keys, wrong types and out-of-range values are :class:`ScenarioError`
naming the file, the table, the key and the value.  The tables' dataclasses are in
:mod:`auvplan.io.scenario.specs`; :func:`build` (:mod:`auvplan.io.scenario.build`) then makes the
World (reading the bathymetry and currents) and checks the mission's start and
goal against it.

Layout (all tables optional except ``[mission]``)::

    name = "..."            description = "..."        seed = 1
    [origin]   lat, lon                                     # geographic scenarios
    [bounds]   x = [min, max]  y = [min, max]  z = [min, max]
    [terrain]  builtin | file, variable, positive, box, resample_m, method, nan_policy
    [terrain.synthetic]  kind = flat|plane|hills|ridge, depth, ...
    [currents] uniform = [u, v, w]   vortices = [{x, y, gamma, delta}, ...]   file = "..."
    [land]     builtin = "gshhg-juan-de-fuca" | file = "coast.gpkg", layer   # coastlines: no-go
    [[obstacles]] type = sphere|ellipsoid, center, radius | semi_axes, yaw_deg, pitch_deg, roll_deg
    [[moving]]    type, radius | semi_axes, motion = linear|circle|waypoints|random-walk, ...
    [mission]  start, goal, route, min_altitude_m, min_depth_m, max_depth_m, obstacle_margin_m
    [[vehicles]]  name, role = leader|follower, start, depth_offset_m     # several vehicles ...
    [formation]   shape = line|column|wedge, spacing_m, changes, ...    # ... flying in formation
    [survey]   polygon | file, sensor, opening_deg | range_m, mounting, altitude_m, overlap, heading_deg
    [vehicle] [planner] [guidance] [avoidance] [sim]   parameters of those components
"""

from __future__ import annotations

import tomllib
from pathlib import Path

from ...errors import DataError, ScenarioError
from ..files.jsonfile import MAX_SCENARIO_BYTES, read_bounded_bytes, source_base
from .build import build
from .builtins import builtin_scenarios, resolve
from .specs import Scenario
from .validate import from_dict

__all__ = ["Scenario", "load", "loads", "scenario_text", "build", "builtin_scenarios", "resolve", "from_dict",
           "MAX_SCENARIO_BYTES"]


def load(scenario: str | Path) -> Scenario:
    """Parse and validate a scenario file (or built-in name) without reading its data files.

    Parameters
    ----------
    scenario : str or pathlib.Path
        A TOML file or a built-in name.

    Returns
    -------
    Scenario
        The validated scenario.
    """
    path = resolve(scenario)
    return loads(scenario_text(path), source=str(path), base_dir=source_base(path))



def scenario_text(path: Path) -> str:
    """The UTF-8 text of a scenario file, read only when it is at most :data:`MAX_SCENARIO_BYTES`.

    Parameters
    ----------
    path : pathlib.Path
        The file.

    Returns
    -------
    str
        Its text.

    Raises
    ------
    ScenarioError
        Naming the file when it is larger, unreadable or not UTF-8.
    """
    try:
        data = read_bounded_bytes(path, MAX_SCENARIO_BYTES, "a scenario file")
    except DataError as exc:
        raise ScenarioError(str(exc)) from exc
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise ScenarioError(f"{path}: line {line}: not UTF-8 text (byte 0x{data[exc.start]:02x} at offset "
                            f"{exc.start}); save the scenario as UTF-8") from exc


def loads(text: str, source: str = "<string>", base_dir: Path | None = None) -> Scenario:
    """Parse and validate scenario TOML text.

    Parameters
    ----------
    text : str
        The TOML.
    source : str, optional
        Its name, for messages.
    base_dir : pathlib.Path, optional
        Folder that relative data paths resolve against.

    Returns
    -------
    Scenario
        The validated scenario.
    """
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{source}: invalid TOML ({exc})") from exc
    except RecursionError as exc:
        raise ScenarioError(f"{source}: invalid TOML (arrays or tables nested too deeply)") from exc
    try:
        return from_dict(data, source, base_dir)
    except RecursionError as exc:
        raise ScenarioError(f"{source}: a value is nested too deeply") from exc
