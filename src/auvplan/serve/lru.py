"""A least-recently-used cache of per-leg figures, keyed by the bytes of the leg's ends."""

from __future__ import annotations

from collections import OrderedDict
from dataclasses import dataclass, field

__all__ = ["LruCache"]


@dataclass
class LruCache:
    """Least-recently-used figures by the bytes of a leg's or segment's ends."""

    size: int = 50_000
    items: OrderedDict[bytes, tuple[float, ...]] = field(default_factory=OrderedDict)

    def get_many(self, keys: list[bytes]) -> tuple[list[tuple[float, ...] | None], list[int]]:
        found: list[tuple[float, ...] | None] = []
        missing = []
        for i, k in enumerate(keys):
            v = self.items.get(k)
            if v is None:
                missing.append(i)
            else:
                self.items.move_to_end(k)
            found.append(v)
        return found, missing

    def put(self, key: bytes, value: tuple[float, ...]) -> None:
        self.items[key] = value
        if len(self.items) > self.size:
            self.items.popitem(last=False)
