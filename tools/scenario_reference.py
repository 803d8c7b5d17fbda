"""Write docs/scenario-reference.md from the scenario JSON Schema (issue 40).

Every table and key of a scenario file, its type, default and description, as the loader knows them:
the page is generated from :func:`auvplan.io.scenario.schema.scenario_schema` (itself generated from the
loader's dataclasses and their numpydoc ``Attributes``), so it cannot drift from the format.
``tests/golden/test_scenario_reference.py`` regenerates it and fails when the file is out of date.

Usage::

    .venv/bin/python tools/scenario_reference.py            # rewrite docs/scenario-reference.md
    .venv/bin/python tools/scenario_reference.py --check    # exit 1 when it is out of date
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path
from typing import Any

from auvplan.io.scenario.schema import SCHEMA_VERSION, scenario_schema

__all__ = ["reference", "main"]

DOC = Path(__file__).parents[1] / "docs" / "scenario-reference.md"


def _clean(text: str) -> str:
    """Markdown of a numpydoc description: ``x`` → `x`, :func:`a.b` → `a.b`, one line, pipes escaped."""
    text = re.sub(r":[a-z]+:`~?([^`]+)`", r"`\1`", text)
    text = text.replace("``", "`")
    return " ".join(text.split()).replace("|", "\\|")


def _type(node: dict[str, Any]) -> str:
    """A short type name of a schema node."""
    if "const" in node:
        return f"`{json.dumps(node['const'])}`"
    if "enum" in node:
        return " \\| ".join(f"`{json.dumps(v)}`" for v in node["enum"])
    for key in ("anyOf", "oneOf"):
        if key in node:
            return " or ".join(dict.fromkeys(_type(a) for a in node[key]))
    t = node.get("type")
    if t == "array":
        if "prefixItems" in node:
            return f"[{', '.join(_type(a) for a in node['prefixItems'])}]"
        items = node.get("items")
        return f"list of {_type(items)}" if isinstance(items, dict) else "list"
    if t == "object":
        return "lat/lon position" if "lat" in node.get("properties", {}) else "table"
    if isinstance(t, list):
        return " or ".join(t)
    return str(t) if t else "any"


def _default(node: dict[str, Any]) -> str:
    if "default" not in node:
        return "required" if node.get("x-required") else ""
    return f"`{json.dumps(node['default'], ensure_ascii=False)}`"


def _is_table(node: dict[str, Any]) -> bool:
    return node.get("type") == "object" and "properties" in node and "lat" not in node["properties"]


def _variants(node: dict[str, Any]) -> list[dict[str, Any]]:
    """The table shapes a key accepts (a table, or several alternatives of tables)."""
    if _is_table(node):
        return [node]
    alts = node.get("anyOf") or node.get("oneOf") or []
    return [a for a in alts if _is_table(a)]


def _section(header: str, node: dict[str, Any], out: list[str]) -> None:
    """One table's keys, then its sub-tables' sections."""
    consts = [f'{k} = {json.dumps(v["const"])}' for k, v in node["properties"].items() if "const" in v]
    head = ["", f"### `{header}`" + (f" ({', '.join(consts)})" if consts else ""), ""]
    if node.get("description"):
        head += [_clean(node["description"]), ""]
    required = set(node.get("required", ()))
    sub: list[tuple[str, dict[str, Any]]] = []
    rows = []
    for key, child in node["properties"].items():
        tables = _variants(child)
        if tables and len(tables) == len(child.get("anyOf", child.get("oneOf", [child]))):
            sub += [(f"{header}.{key}", t) for t in tables]
            continue
        items = child.get("items") if child.get("type") == "array" else None
        if isinstance(items, dict) and _variants(items):
            sub += [(f"[{header}.{key}]", t) for t in _variants(items)]
            continue
        default = "required" if key in required else _default(child)
        rows.append(f"| `{key}` | {_type(child)} | {default} | {_clean(child.get('description', ''))} |")
        sub += [(f"{header}.{key}", t) for t in tables]  # a key that takes a value or a table
    if rows:
        out += [*head, "| key | type | default | description |", "| --- | --- | --- | --- |", *rows]
    for name, table in sub:
        _section(name, table, out)


def reference() -> str:
    """The Markdown text of docs/scenario-reference.md.

    Returns
    -------
    str
        The page, ending with a newline.
    """
    schema = scenario_schema()
    out = ["# Scenario reference", "",
           f"Every table and key of a scenario file (format version {SCHEMA_VERSION}). Generated from the "
           "scenario schema by `tools/scenario_reference.py` (`make docs`); do not edit by hand — "
           "`tests/golden/test_scenario_reference.py` fails when this page is out of date. The same schema is printed "
           "by `auvplan scenario schema`; `auvplan scenario new my.toml` writes a commented template with every "
           "key at its default; how to use each part: [guide.md](guide.md#scenarios).", "",
           "A position (`start`, `goal`, `route` points, obstacle centres) is either `[x, y, z]` in the local "
           "frame (m, x east, y north, z up) or a table `{ lat, lon, depth }` / `{ lat, lon, altitude }` "
           "(degrees WGS 84; metres below the surface or above the seabed). A string key with no default (a file, "
           "a variable name, `tides`, `start_time`) is left unset by omitting it: `key = ''` is refused, naming the "
           "key.", "", "## Top-level keys", "",
           "| key | type | default | description |", "| --- | --- | --- | --- |"]
    required = set(schema.get("required", ()))
    sections: list[tuple[str, dict[str, Any]]] = []
    for key, node in schema["properties"].items():
        tables = _variants(node)
        items = node.get("items") if node.get("type") == "array" else None
        if tables:
            sections += [(key, t) for t in tables]
        elif isinstance(items, dict) and _variants(items):
            sections += [(f"[{key}]", t) for t in _variants(items)]
        else:
            default = "required" if key in required else _default(node)
            out.append(f"| `{key}` | {_type(node)} | {default} | {_clean(node.get('description', ''))} |")
    out += ["", "## Tables"]
    for name, node in sections:
        _section(name, node, out)
    return "\n".join(out) + "\n"


def main(argv: list[str] | None = None) -> int:
    """Write the page, or with ``--check`` report whether it is current.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.

    Returns
    -------
    int
        0 when written or current, 1 when ``--check`` finds it stale.
    """
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check", action="store_true", help="exit 1 when the page is out of date")
    args = ap.parse_args(argv)
    text = reference()
    if args.check:
        current = DOC.read_text() if DOC.exists() else ""
        if current != text:
            print(f"{DOC} is out of date: run tools/scenario_reference.py", file=sys.stderr)
            return 1
        return 0
    DOC.write_text(text)
    print(DOC)
    return 0


if __name__ == "__main__":
    sys.exit(main())
