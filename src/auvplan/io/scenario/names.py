"""Names from a scenario that become folder names, file names or one-line fields, checked at load time.

A ``[[vehicles]]`` name is the folder of that vehicle's results below ``--out`` (its pattern,
:data:`auvplan.guidance.formation.keeping.VEHICLE_NAME`, is enforced by :class:`VehicleSpec` itself); here
the names are also checked against each other and against the files a formation writes beside
them: two names that differ only in case share one folder on a case-insensitive file system, and
a vehicle named ``report.html`` or ``figures`` would collide with the fleet's own files.  The
scenario's ``name`` travels into every result (``run.json``, ``rows.csv``, messages): it may not
hold control characters or path separators, or start with a dot.
"""

from __future__ import annotations

import re
import unicodedata
from collections.abc import Sequence

from ...errors import ScenarioError
from .tables import table_error

__all__ = ["SCENARIO_NAME", "check_scenario_name", "check_vehicle_folders"]

SCENARIO_NAME = re.compile(r"[^\x00-\x1f\x7f/\\.][^\x00-\x1f\x7f/\\]{0,127}")
"""A scenario name: 1-128 characters, no control character, no '/' or '\\', not starting with '.'."""

_INVISIBLE = ("Cc", "Cf", "Zl", "Zp")
"""Unicode categories refused in a scenario name besides :data:`SCENARIO_NAME`'s: C1 controls, format characters
(U+202E right-to-left override turned the messages and the report's title around) and line separators."""

_RESERVED = ("figures", "formation.json", "slots.csv", "scenario.toml", "report.html", "terrain.npz", "source.json",
             ".auvplan-manifest.json", ".auvplan.lock")
"""Names at the top of a formation's ``--out`` that a vehicle folder may not take."""


def check_scenario_name(source: str, name: str) -> None:
    """Raise a :class:`ScenarioError` naming the key when the scenario's ``name`` is unsafe.

    Parameters
    ----------
    source : str
        The scenario file, for the message.
    name : str
        The scenario's ``name``.
    """
    if not SCENARIO_NAME.fullmatch(name) or any(unicodedata.category(c) in _INVISIBLE for c in name):
        raise table_error(f"{source}:", "name", name, "a scenario name is 1-128 characters without control "
                          "or invisible formatting characters, '/' or '\\', not starting with '.'")


def check_vehicle_folders(source: str, names: Sequence[str]) -> None:
    """Raise a :class:`ScenarioError` when two vehicle folders collide, or one collides with a fleet file.

    Parameters
    ----------
    source : str
        The scenario file, for the message.
    names : sequence of str
        The ``[[vehicles]]`` names (each already matching the vehicle-name pattern).
    """
    seen: dict[str, int] = {}
    for i, name in enumerate(names):
        low = name.lower()
        if low in _RESERVED:
            raise ScenarioError(f"{source}: [[vehicles]] #{i + 1} name = {name!r}: is a file or folder the formation "
                                "writes beside the vehicle folders; choose another name")
        if low in seen:
            raise ScenarioError(f"{source}: [[vehicles]] #{i + 1} name = {name!r}: the same folder as vehicle "
                                f"#{seen[low] + 1} {names[seen[low]]!r} on a case-insensitive file system")
        seen[low] = i
