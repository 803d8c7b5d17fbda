"""docs/scenario-reference.md is generated from the scenario schema and kept current (issue 40)."""

from __future__ import annotations

import importlib.util
import re
import sys
from pathlib import Path

from auvplan.io.scenario.schema import scenario_schema

TOOL = Path(__file__).parents[2] / "tools" / "scenario_reference.py"


def _tool():
    spec = importlib.util.spec_from_file_location("scenario_reference", TOOL)
    module = importlib.util.module_from_spec(spec)
    sys.modules["scenario_reference"] = module
    spec.loader.exec_module(module)
    return module


def test_scenario_reference_is_current():
    tool = _tool()
    assert tool.DOC.read_text() == tool.reference(), "stale: run tools/scenario_reference.py"


def test_every_key_of_the_schema_is_in_the_reference():
    """An independent walk of the schema: every table key appears as a row `key` of the page."""
    text = _tool().reference()

    def walk(node):
        for alt in node.get("anyOf", []) + node.get("oneOf", []):
            yield from walk(alt)
        if node.get("type") == "array" and isinstance(node.get("items"), dict):
            yield from walk(node["items"])
        if node.get("type") == "object" and "lat" not in node.get("properties", {}):
            for key, child in node.get("properties", {}).items():
                yield key, child
                yield from walk(child)

    def is_table(child):
        alts = child.get("anyOf", [])
        return child.get("type") == "object" or alts and all(a.get("type") == "object" for a in alts)

    keys = {k for k, child in walk(scenario_schema()) if not is_table(child)}
    missing = sorted(k for k in keys if f"| `{k}` |" not in text
                     and not re.search(rf"^### `\[?[\w.]*\b{k}\]?`", text, re.M))
    assert len(keys) > 150 and not missing, missing
