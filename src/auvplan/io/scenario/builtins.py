"""The built-in scenarios: their list and the file of a name (without importing the loader, so that
``auvplan scenarios`` starts at once)."""

from __future__ import annotations

import tomllib
from importlib import resources
from pathlib import Path

from ...errors import ScenarioError

__all__ = ["builtin_scenarios", "resolve"]


def builtin_scenarios() -> dict[str, str]:
    """List the built-in scenarios with their one-line descriptions.

    Returns
    -------
    dict of str to str
        Name → description.
    """
    out = {}
    folder = resources.files("auvplan") / "data" / "scenarios"
    for entry in sorted(folder.iterdir(), key=lambda e: e.name):
        if entry.name.endswith(".toml"):
            with entry.open("rb") as fh:
                data = tomllib.load(fh)
            out[entry.name[:-5]] = str(data.get("description", "")).strip().splitlines()[0]
    return out


def resolve(scenario: str | Path) -> Path:
    """Return the path of a scenario given as a file path or the name of a built-in scenario.

    Parameters
    ----------
    scenario : str or pathlib.Path
        A TOML file or a built-in name.

    Returns
    -------
    pathlib.Path
        The TOML file.
    """
    p = Path(scenario)
    if p.is_file():
        return p
    builtin = resources.files("auvplan") / "data" / "scenarios" / f"{scenario}.toml"
    if builtin.is_file():
        return Path(str(builtin))
    if (p / "scenario.toml").is_file():  # a results folder (`--scenario DIR`): its saved scenario named
        raise ScenarioError(f"{scenario}: a folder, not a scenario file; the scenario its run saved is "
                            f"{p / 'scenario.toml'}")
    if not str(scenario).strip():  # Path('') is the current folder
        raise ScenarioError(f"{str(scenario)!r}: an empty scenario name; give a TOML file or a built-in scenario")
    if p.is_dir() or p.exists():  # was 'no such scenario file' for what is there (hostile round 20)
        kind = "a folder" if p.is_dir() else "not a regular file (a FIFO, a device or a socket)"
        raise ScenarioError(f"{scenario}: {kind}, not a scenario file; give a TOML file or a built-in scenario")
    names = ", ".join(builtin_scenarios())
    raise ScenarioError(f"{scenario}: no such scenario file, and not a built-in scenario ({names})")
