"""Hypothesis strategies that mutate valid scenario documents (the built-ins) into hostile ones.

A mutation picks a place in the parsed TOML document (a table key or an array element, at any
depth) and does one of: change the value's type, put NaN / ±inf / a huge, negative or zero
number there, delete the key, add an unknown key, wrap the value in an array or a table (wrong
nesting), or unwrap it.  Up to three mutations per document.
"""

from __future__ import annotations

import copy
import math
import tomllib
from importlib import resources

from hypothesis import strategies as st

__all__ = ["BUILTINS", "documents", "paths_of"]


def _builtins() -> dict[str, dict]:
    folder = resources.files("auvplan") / "data" / "scenarios"
    out = {}
    for entry in sorted(folder.iterdir(), key=lambda e: e.name):
        if entry.name.endswith(".toml"):
            with entry.open("rb") as fh:
                out[entry.name[:-5]] = tomllib.load(fh)
    return out


BUILTINS = _builtins()
"""Parsed built-in scenarios, by name."""

NUMBERS = [math.nan, math.inf, -math.inf, 0, 0.0, -1, -1.0, -1e9, 1e-300, 1e-12, 1e9, 1e15, 1e16, 1e300, 10**19,
           2**63, -(2**63), 3, 7.5]
OTHERS = ["", "x", "sphere", "grid", "random-walk", True, False, [], {}, [1.0], [1.0, 2.0, 3.0], [[0.0, 0.0, 0.0]],
          {"type": "sphere"}, [[1.0, 2.0], [3.0]], "é\u0000"]


def paths_of(doc, prefix=()):
    """Every place in ``doc``: tuples of keys / indices."""
    out = []
    if isinstance(doc, dict):
        for k, v in doc.items():
            out.append(prefix + (k,))
            out.extend(paths_of(v, prefix + (k,)))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            out.append(prefix + (i,))
            out.extend(paths_of(v, prefix + (i,)))
    return out


def _parent(doc, path):
    node = doc
    for k in path[:-1]:
        node = node[k]
    return node


def _mutate(doc, path, kind: str, value):
    parent = _parent(doc, path)
    key = path[-1]
    old = parent[key]
    if kind == "delete":
        del parent[key]
    elif kind == "replace":
        parent[key] = value
    elif kind == "wrap-array":
        parent[key] = [old]
    elif kind == "wrap-table":
        parent[key] = {"value": old}
    elif kind == "unwrap":
        if isinstance(old, list) and old:
            parent[key] = old[0]
        elif isinstance(old, dict) and old:
            parent[key] = next(iter(old.values()))
    elif kind == "extra-key":
        target = old if isinstance(old, dict) else parent if isinstance(parent, dict) else None
        if target is not None:
            target["unexpected_key"] = value
    elif kind == "scale" and isinstance(old, (int, float)) and not isinstance(old, bool):
        parent[key] = type(old)(old * value) if math.isfinite(old * value) else old * value
    elif kind == "scale" and isinstance(old, list):
        parent[key] = [v * value if isinstance(v, (int, float)) and not isinstance(v, bool) else v for v in old]


def _numeric_leaves(doc) -> list:
    out = []
    for p in paths_of(doc):
        v = _parent(doc, p)[p[-1]]
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            out.append(p)
    return out


def _known_keys() -> list[tuple[str, ...]]:
    """Every key the loader knows, as a path (section, key) or (section, sub-table, key): a mutation
    can then set keys the built-ins leave at their defaults (``[currents] file``, ``[planner.grid]``)."""
    import dataclasses

    from auvplan.io.scenario.specs import SECTIONS

    out = []
    for section, cls in SECTIONS.items():
        for f in dataclasses.fields(cls):
            if not f.init or f.name.startswith("_"):
                continue
            out.append((section, f.name))
            sub = f.default_factory() if f.default_factory is not dataclasses.MISSING else None
            if dataclasses.is_dataclass(sub):
                out += [(section, f.name, g.name) for g in dataclasses.fields(sub) if g.init]
    return out


KNOWN_KEYS = _known_keys()


def _set_known(doc, path, value) -> None:
    node = doc
    for k in path[:-1]:
        if not isinstance(node.get(k), dict):
            node[k] = {}
        node = node[k]
    node[path[-1]] = value


@st.composite
def documents(draw, max_mutations: int = 3, numeric: bool = False):
    """``(name, document, paths mutated)``: a built-in scenario with 1..max_mutations mutations.

    ``numeric=True`` only rescales numbers (a document that often stays valid: for the tests that
    plan and fly what validates)."""
    name = draw(st.sampled_from(sorted(BUILTINS)))
    doc = copy.deepcopy(BUILTINS[name])
    touched = []
    for _ in range(draw(st.integers(1, max_mutations))):
        places = _numeric_leaves(doc) if numeric else paths_of(doc)
        if not places:
            break
        path = draw(st.sampled_from(places))
        kind = "scale" if numeric else draw(st.sampled_from(
            ["replace", "replace", "replace", "delete", "wrap-array", "wrap-table", "unwrap", "extra-key", "scale",
             "scale", "known-key", "known-key"]))
        if numeric:
            value = draw(st.sampled_from([0, -1, 0.5, 0.9, 1.1, 2, 10, 100, 1e4]))
        elif kind == "scale":
            value = draw(st.sampled_from([0, -1, 1e-9, 1e6, 1e12, 1e300, math.inf, math.nan]))
        else:
            value = draw(st.one_of(st.sampled_from(NUMBERS), st.sampled_from(OTHERS),
                                   st.floats(allow_nan=True, allow_infinity=True),
                                   st.integers(-(2**70), 2**70), st.text(max_size=5)))
        if kind == "known-key":
            path = draw(st.sampled_from(KNOWN_KEYS))
            _set_known(doc, path, copy.deepcopy(value))
        else:
            _mutate(doc, path, kind, copy.deepcopy(value))
        touched.append(path)
    return name, doc, touched
