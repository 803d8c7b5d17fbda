"""A parsed scenario document (the dict :mod:`tomllib` returns) written back as TOML text.

The page edits a scenario as data (``[vehicle] speed``, ``[mission] start_time``, a ``[survey]``
polygon); the edited document is written as TOML and read back by the scenario loader, so it is
validated by exactly the code the command line uses, and saved as the results folder's
``scenario.toml``.  Writing is the inverse of :func:`tomllib.loads` on these documents:
tables, arrays of tables, inline tables inside arrays, strings, numbers, booleans and dates.
"""

from __future__ import annotations

import datetime as dt
import json
import math
import re
from typing import Any

__all__ = ["dumps"]

_BARE = re.compile(r"^[A-Za-z0-9_-]+$")


def _key(k: str) -> str:
    return k if _BARE.match(k) else json.dumps(k)


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)  # a JSON string is a TOML basic string
    if isinstance(v, (dt.datetime, dt.date, dt.time)):
        return v.isoformat()
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_key(k)} = {_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(f"cannot write {type(v).__name__} as TOML")


def _is_table_array(v: Any) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, dict) for x in v)


def _table(doc: dict[str, Any], path: list[str], lines: list[str]) -> None:
    scalars = [(k, v) for k, v in doc.items() if not isinstance(v, dict) and not _is_table_array(v)]
    for k, v in scalars:
        lines.append(f"{_key(k)} = {_value(v)}")
    for k, v in doc.items():
        if isinstance(v, dict):
            lines += ["", f"[{'.'.join(map(_key, [*path, k]))}]"]
            _table(v, [*path, k], lines)
        elif _is_table_array(v):
            for item in v:
                lines += ["", f"[[{'.'.join(map(_key, [*path, k]))}]]"]
                _table(item, [*path, k], lines)


def dumps(doc: dict[str, Any]) -> str:
    """Write a parsed TOML document as TOML text.

    Parameters
    ----------
    doc : dict
        A document as :func:`tomllib.loads` returns it.

    Returns
    -------
    str
        Text that :func:`tomllib.loads` reads back to ``doc``.
    """
    lines: list[str] = []
    _table(doc, [], lines)
    return "\n".join(lines).lstrip("\n") + "\n"
