"""The scenario's JSON Schema and a commented template, generated from the loader's own tables.

Nothing here is a second copy of the scenario format: the schema walks the same frozen
dataclasses (and type hints) that :mod:`auvplan.io.scenario.tables` converts TOML with, and takes each
key's description from the dataclass's numpydoc ``Attributes`` section.  Checks that live in
``__post_init__`` (enumerations, cross-key rules, ranges other than "finite") are enforced by the
loader only; the schema gives editors completion, types, defaults and documentation.
"""

from __future__ import annotations

import dataclasses
import math
import re
import textwrap
import types
import typing
from collections.abc import Iterator
from typing import Any

from ..._version import __version__
from ...guidance.formation.keeping import VehicleSpec
from . import specs
from . import validate as sc
from .tables import MAX_MAGNITUDE

__all__ = ["SCHEMA_VERSION", "scenario_schema", "template", "field_docs", "GEO_POSITION"]

SCHEMA_VERSION = "1.0"
"""Version of the scenario format (bumped when keys change meaning or disappear)."""

_SHAPES = {"sphere": sc._SphereSpec, "ellipsoid": sc._EllipsoidSpec}
_MOTIONS = {"linear": sc._LinearSpec, "circle": sc._CircleSpec, "waypoints": sc._WaypointsSpec,
            "random-walk": sc._RandomWalkSpec}


def field_docs(cls: type) -> dict[str, str]:
    """Read each key's one-line description from a dataclass's numpydoc ``Attributes`` section.

    Parameters
    ----------
    cls : type
        A documented dataclass.

    Returns
    -------
    dict of str to str
        Key → description (empty when the class has no Attributes section).
    """
    doc = cls.__doc__ or ""
    m = re.search(r"\n\s*Attributes\n\s*-+\n(.*?)(\n\s*\n\s*[A-Z][a-z]+\n\s*-+\n|\Z)", doc, re.S)
    if not m:
        return {}
    out: dict[str, str] = {}
    names: list[str] = []
    for line in m.group(1).splitlines():
        head = re.match(r"^\s{0,8}([A-Za-z_][\w, ]*?)\s*:\s*\S", line)
        if head and not line.startswith(" " * 8):
            names = [n.strip() for n in head.group(1).split(",")]
            for n in names:
                out[n] = ""
        elif names and line.strip():
            for n in names:
                out[n] = (out[n] + " " + line.strip()).strip()
    return {k: " ".join(v.split()) for k, v in out.items()}


def _number(integer: bool) -> dict[str, Any]:
    return {"type": "integer" if integer else "number", "minimum": -MAX_MAGNITUDE, "maximum": MAX_MAGNITUDE}


def _type_schema(tp: Any) -> dict[str, Any]:
    origin, args = typing.get_origin(tp), typing.get_args(tp)
    if origin in (typing.Union, types.UnionType):
        alts = [_type_schema(a) for a in args if a is not type(None)]
        return alts[0] if len(alts) == 1 else {"anyOf": alts}
    if tp is float:
        return _number(False)
    if tp is int:
        return _number(True)
    if tp is bool:
        return {"type": "boolean"}
    if tp is str:
        return {"type": "string"}
    if origin is tuple:
        if len(args) == 2 and args[1] is Ellipsis:
            return {"type": "array", "items": _type_schema(args[0])}
        return {"type": "array", "prefixItems": [_type_schema(a) for a in args], "items": False,
                "minItems": len(args), "maxItems": len(args)}
    if dataclasses.is_dataclass(tp):
        return table_schema(typing.cast(type, tp))
    return {}


def _json_default(value: Any) -> Any:
    if isinstance(value, tuple):
        return [_json_default(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _fields(cls: type) -> Iterator[tuple[str, Any, bool, Any]]:
    hints = typing.get_type_hints(cls)
    for f in dataclasses.fields(cls):
        if f.init and not f.name.startswith("_"):
            required = f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING
            default = None if required else (f.default if f.default is not dataclasses.MISSING
                                             else f.default_factory())  # type: ignore[operator]
            yield f.name, hints[f.name], required, default


def table_schema(cls: type, skip: tuple[str, ...] = ()) -> dict[str, Any]:
    """Make the JSON Schema of one TOML table from the dataclass ``cls`` (unknown keys rejected).

    Parameters
    ----------
    cls : type
        The table's dataclass.
    skip : tuple of str, optional
        Fields left out (handled by the caller).

    Returns
    -------
    dict
        The table's schema: properties with types, defaults and descriptions.
    """
    docs = field_docs(cls)
    props, required = {}, []
    for name, tp, req, default in _fields(cls):
        if name in skip:
            continue
        p = _type_schema(tp)
        if not req and default in ("", None) and name != "name":  # '' refused, not read as unset (a name: unnamed)
            for alt in p.get("anyOf", [p]):
                if alt.get("type") == "string":
                    alt["minLength"] = 1
        if docs.get(name):
            p = {"description": docs[name], **p}
        if req:
            required.append(name)
        elif not dataclasses.is_dataclass(default) and _json_default(default) is not None:
            p["default"] = _json_default(default)
        props[name] = p
    out = {"type": "object", "properties": props, "additionalProperties": False}
    if (cls.__doc__ or "").strip():
        out = {"description": (cls.__doc__ or "").strip().splitlines()[0], **out}
    if required:
        out["required"] = required
    return out


def _obstacle_schema() -> dict[str, Any]:
    alts = []
    for kind, cls in _SHAPES.items():
        t = table_schema(cls)
        t["properties"]["type"] = {"const": kind}
        if kind == "sphere":  # type may be omitted for a sphere
            t["required"] = [r for r in t["required"] if r != "type"]
        alts.append(t)
    return {"oneOf": alts}


def _moving_schema() -> dict[str, Any]:
    alts = []
    for shape, scls in _SHAPES.items():
        for motion, mcls in _MOTIONS.items():
            s = table_schema(scls, skip=("center",))
            m = table_schema(mcls)
            props = {**s["properties"], **m["properties"],
                     "type": {"const": shape}, "motion": {"const": motion},
                     "name": {"type": "string"}, "appears": _number(False), "disappears": _number(False)}
            req = sorted({*s.get("required", []), *m.get("required", []), "motion"} - {"type"} |
                         ({"type"} if shape != "sphere" else set()))
            alts.append({"type": "object", "properties": props, "required": req, "additionalProperties": False})
    return {"oneOf": alts}


def _zones_schema() -> dict[str, Any]:
    """``[[zones]]`` (:mod:`auvplan.io.data.vector.zones`): one geometry key, a depth band, a name."""
    pair = {"type": "array", "items": {"type": "number"}, "minItems": 2, "maxItems": 2}
    depth = {"type": "number", "minimum": 0}
    props = {"name": {"type": "string", "minLength": 1},
             "polygon": {"type": "array", "items": pair, "minItems": 3}, "line": {"type": "array", "items": pair,
                                                                                  "minItems": 2},
             "point": pair, "buffer_m": {"type": "number", "exclusiveMinimum": 0},
             "radius_m": {"type": "number", "exclusiveMinimum": 0}, "top_m": depth, "bottom_m": depth,
             "above_seabed_m": {"type": "number", "exclusiveMinimum": 0},
             "file": {"type": "string", "minLength": 1}, "layer": {"type": "string", "minLength": 1},
             "where": {"type": "string", "minLength": 1}}
    item = {"type": "object", "properties": props, "required": ["name"], "additionalProperties": False,
            "oneOf": [{"required": [k]} for k in ("polygon", "line", "point", "file")]}
    return {"type": "array", "items": item, "description": "Charted no-go zones: a footprint ([lat, lon] or "
            "metre [x, y] pairs, or a vector file's features) times a depth band (docs/zones.md)."}


def scenario_schema() -> dict[str, Any]:
    """Make the versioned JSON Schema (draft 2020-12) of a scenario document.

    Returns
    -------
    dict
        The schema, generated from the loader's tables (never stricter than the loader).
    """
    sections = {key: table_schema(cls) for key, cls in specs.SECTIONS.items()}
    terrain = {"anyOf": [sections.pop("terrain"), {
        "type": "object", "properties": {"synthetic": table_schema(specs.SyntheticTerrainSpec)},
        "required": ["synthetic"], "additionalProperties": False}]}
    props = {
        "name": {"type": "string", "description": "Scenario name (default: the file name)."},
        "description": {"type": "string"},
        "seed": {"type": "integer", "minimum": 0, "maximum": 2**63 - 1, "description": "Default random seed."},
        **sections,
        "terrain": terrain,
        "obstacles": {"type": "array", "items": _obstacle_schema(), "description": "Static obstacles."},
        "moving": {"type": "array", "items": _moving_schema(), "description": "Moving obstacles."},
        "vehicles": {"type": "array", "items": table_schema(VehicleSpec), "minItems": 2,
                     "description": "Several vehicles flying the route in [formation]."},
        "zones": _zones_schema(),
    }
    for table in (props["mission"], props["obstacles"], props["moving"], props["vehicles"]):
        _geographic_positions(table)
    from .defaults import PRESETS  # issue 51: published figures of a vehicle, under the explicit keys

    vehicle: dict[str, Any] = sections["vehicle"]
    vehicle["properties"] = {"preset": {"enum": list(PRESETS), "description": (
        "A vehicle's published figures (speed, battery, hotel load, depth rating, pitch and turn limits; "
        "docs/missions.md); every key given here overrides its preset value.")}, **vehicle["properties"]}
    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "$id": f"https://auvplan.invalid/schema/scenario-{SCHEMA_VERSION}.json",
        "title": "auvplan scenario",
        "description": f"auvplan scenario format {SCHEMA_VERSION} (auvplan {__version__}); TOML files, "
                       "checked by `auvplan validate`.",
        "x-auvplan-schema-version": SCHEMA_VERSION,
        "type": "object",
        "properties": props,
        "required": ["mission"],
        "additionalProperties": False,
    }


GEO_POSITION: dict[str, Any] = {
    "type": "object",
    "description": "A geographic position (WGS 84, degrees) with a depth below the surface or an altitude above "
                   "the seabed (m); see auvplan.io.scenario.inputs.geoinput.",
    "properties": {"lat": {"type": "number", "minimum": -90, "maximum": 90},
                   "lon": {"type": "number", "minimum": -360, "maximum": 360},
                   "depth": _number(False), "altitude": {"type": "number", "minimum": 0, "maximum": MAX_MAGNITUDE}},
    "required": ["lat", "lon"],
    "oneOf": [{"required": ["depth"]}, {"required": ["altitude"]}],
    "additionalProperties": False,
}
"""``{ lat, lon, depth | altitude }``: accepted wherever a scenario takes a metre triple."""


def _is_triple(node: Any) -> bool:
    return isinstance(node, dict) and node.get("type") == "array" and len(node.get("prefixItems", ())) == 3


def _geographic_positions(node: Any) -> None:
    """Let every position of a table (start, goal, center, route and points items) be geographic too."""
    if isinstance(node, list):
        for item in node:
            _geographic_positions(item)
        return
    if not isinstance(node, dict):
        return
    for key, sub in list(node.get("properties", {}).items()):
        if key in ("start", "goal", "center") and _is_triple(sub):
            node["properties"][key] = {"anyOf": [sub, GEO_POSITION]}
        elif key in ("route", "points") and isinstance(sub, dict) and _is_triple(sub.get("items")):
            sub["items"] = {"anyOf": [sub["items"], GEO_POSITION]}
    for key in ("oneOf", "anyOf", "items"):
        if key in node:
            _geographic_positions(node[key])


def _toml(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, (tuple, list)):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return repr(value)


def _commented_table(header: str, cls: type, given: dict[str, Any] | None = None) -> list[str]:
    docs, given = field_docs(cls), given or {}
    lines, nested = [f"[{header}]"], []
    for name, _, _, default in _fields(cls):
        if dataclasses.is_dataclass(default):
            nested.append((f"{header}.{name}", type(default)))
            continue
        if docs.get(name):
            lines += textwrap.wrap(docs[name].replace("``", ""), 100, initial_indent="# ", subsequent_indent="#   ")
        if name in given:
            lines.append(f"{name} = {_toml(given[name])}")
        elif isinstance(default, float) and not math.isfinite(default):
            lines.append(f"# {name} = (no limit when omitted)")
        elif default is None:  # resolved from another key when omitted (see its description)
            lines.append(f"# {name} (omitted: see above)")
        else:
            lines.append(f"# {name} = {_toml(default)}")
    for sub, subcls in nested:
        lines += [""] + [f"# {line}" if not line.startswith("#") else line
                         for line in _commented_table(sub, subcls)]
    return lines


_TEMPLATE_EXAMPLES = (
    "# [[obstacles]]",
    '# type = "sphere"',
    "# center = [1000.0, 1400.0, -50.0]",
    "# radius = 20.0",
    "",
    "# [[moving]]",
    '# type = "sphere"',
    "# radius = 5.0",
    '# motion = "linear"  # or circle, waypoints, random-walk',
    "# start = [1500.0, 0.0, -40.0]",
    "# velocity = [0.0, 0.5, 0.0]",
    "",
    "# [[zones]]  # a charted no-go zone: polygon, line + buffer_m, point + radius_m, or file (docs/zones.md)",
    '# name = "wreck"',
    "# point = [1000.0, 600.0]  # [x, y] m, or [lat, lon] with [origin]",
    "# radius_m = 50.0",
    "# above_seabed_m = 20.0  # the band: the 20 m above the seabed; or top_m / bottom_m (depths, positive down)",
    "",
    "# Optional tables not written out here (every key: docs/scenario-reference.md): [land] coastlines as no-go,",
    "# [survey] coverage lines (docs/survey.md), [navigation] dead reckoning and fixes (docs/navigation.md),",
    "# [[vehicles]] and [formation] several vehicles (docs/guide.md).",
    "",
)
"""The template's commented-out obstacle, moving obstacle and zone, and where the tables not written out are
documented."""


def _template_head(name: str) -> list[str]:
    """The template's head: name, description and seed, the bounds, a synthetic seabed and the currents, then the
    commented-out examples (:data:`_TEMPLATE_EXAMPLES`)."""
    return [
        f"# auvplan scenario (format {SCHEMA_VERSION}). Check it with `auvplan validate FILE`;",
        "# the JSON Schema: `auvplan scenario schema`. Uncomment a key to change it from its default.",
        f'name = "{name}"',
        'description = "A synthetic 2 km x 2 km box with a ridge; replace [terrain] with real data."',
        "seed = 1",
        "",
        "# [origin] lat/lon is required with real bathymetry ([terrain] file or builtin), unless the positions",
        "# are written in degrees: start = { lat = .., lon = .., depth = .. } (or altitude = .. above the seabed)",
        "# [origin]",
        "# lat = 14.7601",
        "# lon = 158.4009",
        "",
        "[bounds]",
        "x = [0.0, 2000.0]",
        "y = [0.0, 2000.0]",
        "z = [-120.0, 0.0]",
        "",
        "# or: [terrain] file = \"grid.nc\" (NetCDF: GEBCO, ETOPO, GMT, CF), box = [lat_min, lat_max, lon_min, "
        "lon_max], resample_m = 100.0",
        "[terrain.synthetic]",
        'kind = "ridge"',
        "depth = 100.0",
        "ridge_x = 1000.0",
        "ridge_width = 300.0",
        "height = 40.0",
        "",
        "[currents]",
        "uniform = [0.1, 0.0, 0.0]  # or vortices = [{ x = ..., y = ..., gamma = ..., delta = ... }], or file",
        "",
        *_TEMPLATE_EXAMPLES,
    ]


def template(name: str = "my-mission") -> str:
    """Write a commented scenario that validates as it is.

    A synthetic seabed, a start and a goal, and every other key of every table commented out at
    its default, with its description.

    Parameters
    ----------
    name : str, optional
        The scenario's name.

    Returns
    -------
    str
        The TOML text.
    """
    head = _template_head(name)
    mission = {"start": (100.0, 1000.0, -40.0), "goal": (1900.0, 1000.0, -40.0), "min_altitude_m": 10.0}
    body = _commented_table("mission", specs.MissionSpec, mission)
    for key in ("vehicle", "planner", "guidance", "avoidance", "sim", "limits", "endurance"):
        body += [""] + _commented_table(key, specs.SECTIONS[key])
    return "\n".join(head + body) + "\n"
