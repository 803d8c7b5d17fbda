"""Typed conversion of TOML tables into frozen parameter dataclasses.

One mechanism serves every scenario section: the dataclass's field names are
the allowed keys (unknown keys are errors), its type hints are the allowed
types (``float``, ``int``, ``bool``, ``str``, fixed and variable tuples, nested
dataclasses and tuples of them), and its ``__post_init__`` checks ranges.  A string key whose default
is '' (unset: a file, a variable name, the tides) refuses an explicit '' instead of reading it as absent (a
``name`` may be '': unnamed).
Every error is a :class:`ScenarioError` naming the file, the table, the key
and the value.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import types
import typing
from typing import Any, NoReturn

from ...errors import ScenarioError

__all__ = ["build_dataclass", "table_error", "MAX_MAGNITUDE"]

MAX_MAGNITUDE = 1.0e15
"""Largest magnitude of any number in a scenario: beyond it products and squares of scenario
values overflow or lose every significant digit (coordinates of the whole Earth are ~4e7 m)."""


_EMPTY = "an empty string is not a value (omit the key to leave it unset)"
"""Why ``key = ''`` is refused for a string key whose default is '' (unset): it was silently read as absent."""


def table_error(where: str, key: str, value: Any, problem: str) -> ScenarioError:
    """Make a ScenarioError of the form ``file: [table] key = value: problem``.

    Parameters
    ----------
    where : str
        ``file: [table]``.
    key : str
        The key.
    value : object
        Its value (shown with ``repr``-like TOML formatting).
    problem : str
        What is wrong.

    Returns
    -------
    ScenarioError
        The error, to be raised.
    """
    shown = repr(value)
    if len(shown) > 80:
        shown = shown[:77] + "..."
    return ScenarioError(f"{where} {key} = {shown}: {problem}")


def _convert(value: Any, tp: Any, where: str, key: str) -> Any:
    origin = typing.get_origin(tp)
    args = typing.get_args(tp)
    if origin in (typing.Union, types.UnionType):
        errors: list[ScenarioError] = []
        alts = [a for a in args if a is not type(None)]
        for alt in alts:
            try:
                return _convert(value, alt, where, key)
            except ScenarioError as exc:
                errors.append(exc)
        fits = [e for a, e in zip(alts, errors) if _fits(value, a)]
        if len(fits) == 1:  # the alternative the value is written as says what is wrong inside it
            raise fits[0]
        if len(errors) == 1:
            raise errors[0]
        return _raise(table_error(where, key, value, "expected " + " or ".join(_type_name(a) for a in alts)))
    if tp is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise table_error(where, key, value, "expected a number")
        if math.isnan(value):
            raise table_error(where, key, value, "NaN is not allowed")
        if math.isinf(value):
            raise table_error(where, key, value, "must be finite (omit the key for its default)")
        if abs(value) > MAX_MAGNITUDE:
            raise table_error(where, key, value, f"out of range (|value| <= {MAX_MAGNITUDE:g})")
        return float(value)
    if tp is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise table_error(where, key, value, "expected an integer")
        if abs(value) > MAX_MAGNITUDE:
            raise table_error(where, key, value, f"out of range (|value| <= {MAX_MAGNITUDE:g})")
        return value
    if tp is bool:
        if not isinstance(value, bool):
            raise table_error(where, key, value, "expected true or false")
        return value
    if tp is str:
        if not isinstance(value, str):
            raise table_error(where, key, value, "expected a string")
        return value
    if origin is tuple:
        if not isinstance(value, (list, tuple)):
            raise table_error(where, key, value, "expected an array")
        if len(args) == 2 and args[1] is Ellipsis:
            return tuple(_convert(v, args[0], where, f"{key}[{i}]") for i, v in enumerate(value))
        if len(value) != len(args):
            raise table_error(where, key, value, f"expected an array of {len(args)} values")
        return tuple(_convert(v, a, where, f"{key}[{i}]") for i, (v, a) in enumerate(zip(value, args)))
    if dataclasses.is_dataclass(tp):
        if not isinstance(value, dict):
            raise table_error(where, key, value, "expected a table")
        sub = f"{where[:-1]}.{key}]" if where.endswith("]") else where
        return build_dataclass(typing.cast(type, tp), value, sub)
    if tp is Any:
        return value
    raise TypeError(f"unsupported field type {tp!r} for {key}")  # a programming error, not user input


def _fits(value: Any, tp: Any) -> bool:
    """Whether ``value`` is written as the TOML kind of type ``tp`` (a table for a dataclass, an array for a tuple)."""
    if dataclasses.is_dataclass(tp):
        return isinstance(value, dict)
    if typing.get_origin(tp) is tuple:
        return isinstance(value, (list, tuple))
    return isinstance(value, str) if tp is str else False


def _raise(exc: Exception) -> NoReturn:
    raise exc


def _type_name(tp: Any) -> str:
    if dataclasses.is_dataclass(tp):
        return "a table"
    if typing.get_origin(tp) is tuple:
        return "an array"
    return {float: "a number", int: "an integer", bool: "true or false", str: "a string"}.get(tp, str(tp))


@functools.cache
def _type_hints(cls: type) -> dict[str, Any]:
    """``typing.get_type_hints(cls)``, once per class (evaluating the string annotations compiles each of them:
    a scenario document builds a few dozen tables, a hostile-document fuzz run thousands)."""
    return typing.get_type_hints(cls)


def build_dataclass(cls: type, table: dict[str, Any], where: str, *, skip: tuple[str, ...] = ()) -> Any:
    """Instantiate the frozen dataclass ``cls`` from a TOML ``table``.

    Parameters
    ----------
    cls : type
        A dataclass; its non-underscore init fields are the accepted keys.
    table : dict
        Parsed TOML table.
    where : str
        Prefix for messages, e.g. ``"scenario.toml: [planner]"``.
    skip : tuple of str
        Keys handled by the caller (accepted, not passed on).

    Returns
    -------
    object
        The instance of ``cls``.
    """
    if not isinstance(table, dict):
        raise ScenarioError(f"{where}: expected a table, got {table!r}")
    hints = _type_hints(cls)
    fields = {f.name: f for f in dataclasses.fields(cls) if f.init and not f.name.startswith("_")}
    for key in table:
        if key not in fields and key not in skip:
            allowed = ", ".join(sorted(fields))
            raise ScenarioError(f"{where} unknown key {key!r} (allowed: {allowed})")
    kwargs = {}
    for name in fields:
        if name in table:
            kwargs[name] = _convert(table[name], hints[name], where, name)
            if kwargs[name] == "" and fields[name].default in ("", None) and name != "name":  # a name may be ''
                raise table_error(where, name, "", _EMPTY)  # was read as absent (a file, a variable, the tides)
    missing = [
        n for n, f in fields.items()
        if n not in kwargs and f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING
    ]
    if missing:
        raise ScenarioError(f"{where} missing required key {missing[0]!r}")
    try:
        return cls(**kwargs)
    except (ValueError, TypeError) as exc:
        raise ScenarioError(f"{where} {exc}") from exc
