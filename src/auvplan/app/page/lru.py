"""A least-recently-used cache of per-leg figures, keyed by the bytes of the leg's ends."""

from __future__ import annotations

from collections import OrderedDict
from dataclasses import dataclass, field

__all__ = ["LruCache"]


@dataclass
class LruCache:
    """Least-recently-used figures by the bytes of a leg's or segment's ends.

    Attributes
    ----------
    size : int
        Entries kept at most; putting one more forgets the least recently used.
    items : collections.OrderedDict
        The figures by key, least recently used first.
    """

    size: int = 50_000
    items: OrderedDict[bytes, tuple[float, ...]] = field(default_factory=OrderedDict)

    def get_many(self, keys: list[bytes]) -> tuple[list[tuple[float, ...] | None], list[int]]:
        """Look up many keys at once; each one found becomes the most recently used.

        Parameters
        ----------
        keys : list of bytes
            The keys (e.g. the bytes of each leg's two ends).

        Returns
        -------
        found : list
            Each key's figures, or ``None`` where it is not cached.
        missing : list of int
            The positions in ``keys`` of those not cached.
        """
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
        """Remember ``value`` under ``key`` (forgetting the least recently used beyond ``size``).

        Parameters
        ----------
        key : bytes
            The key.
        value : tuple of float
            The figures.
        """
        self.items[key] = value
        if len(self.items) > self.size:
            self.items.popitem(last=False)
