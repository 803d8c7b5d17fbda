"""One parse of a mission file per check.

``mission check`` reads a file with several readers — the waypoints (up to three times: the seabed check, the
energy and the terrain legs), the speeds, the holds, the datum and envelope, the tail-first legs, the terrain
frame — and each parsed the JSON of a ``.plan`` or GeoJSON mission again and walked its items again: a 10⁵-item
``.plan`` took 25 s.  Inside :func:`parse_once` the JSON of a text is parsed once (:func:`loads`, keyed by the
text itself, so an edited file is never served stale) and a value derived from it kept beside it
(:func:`remembered`: the ``.plan``'s item walk); outside it every call parses as before, and nothing is kept after
it (a ``serve`` process keeps no document alive).  The readers never change a parsed document.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any, TypeVar

__all__ = ["parse_once", "loads", "remembered"]

T = TypeVar("T")

_MEMO: ContextVar[dict[str, tuple[Any, Any]] | None] = ContextVar("auvplan_mission_parse", default=None)


@contextmanager
def parse_once() -> Iterator[None]:
    """Within the block, :func:`loads` parses a text once and :func:`remembered` computes once per document.

    Yields
    ------
    None
    """
    token = _MEMO.set({})
    try:
        yield
    finally:
        _MEMO.reset(token)


def loads(text: str) -> Any:
    """``json.loads(text)``, parsed once per text within :func:`parse_once`.

    Parameters
    ----------
    text : str
        The file's text.

    Returns
    -------
    object
        The parsed document (shared: never to be changed).
    """
    memo = _MEMO.get()
    if memo is None:
        return json.loads(text)
    hit = memo.get("json")
    if hit is not None and (hit[0] is text or hit[0] == text):
        return hit[1]
    doc = json.loads(text)
    memo.clear()  # one document at a time: what was derived from another goes with it
    memo["json"] = (text, doc)
    return doc


def remembered(kind: str, doc: Any, compute: Callable[[], T]) -> T:
    """``compute()`` of the document ``doc``, computed once per document within :func:`parse_once`.

    Parameters
    ----------
    kind : str
        What is computed (one value of each kind per document).
    doc : object
        The document it is computed from (kept by identity).
    compute : callable
        The computation; an exception is raised again at each call, never kept.

    Returns
    -------
    object
        Its value (shared: never to be changed).
    """
    memo = _MEMO.get()
    if memo is None:
        return compute()
    hit = memo.get(kind)
    if hit is not None and hit[0] is doc:
        return hit[1]  # type: ignore[no-any-return]
    value = compute()
    memo[kind] = (doc, value)
    return value
