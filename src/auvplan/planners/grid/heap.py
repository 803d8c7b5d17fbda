"""The indexed binary heap of the lattice search (compiled): ``int32`` node ids with their keys inline.

``heap[i]`` is a node id and ``hkey[i]`` its key, both in heap order, so a sift compares keys that
sit next to each other in memory instead of loading ``key[heap[c]]`` from anywhere in a per-node
array (one cache miss per comparison on a lattice of millions of nodes).  ``pos[u]`` is ``u``'s
index in the heap (-1 never queued or free to queue again, -2 settled), so a node's key can fall
and the node move up in place (decrease-key).
"""

from __future__ import annotations

from typing import Any

from ..._types import FloatArray
from ...runtime.jit import kernel

__all__ = ["push", "pop"]


@kernel
def _sift_up(heap: Any, hkey: FloatArray, pos: Any, i: int, node: int, k: float) -> None:
    while i > 0:
        parent = (i - 1) >> 1
        if hkey[parent] <= k:
            break
        heap[i] = heap[parent]
        hkey[i] = hkey[parent]
        pos[heap[i]] = i
        i = parent
    heap[i] = node
    hkey[i] = k
    pos[node] = i


@kernel
def _sift_down(heap: Any, hkey: FloatArray, pos: Any, size: int) -> None:
    node, k = heap[0], hkey[0]
    i = 0
    while True:
        c = 2 * i + 1
        if c >= size:
            break
        if c + 1 < size and hkey[c + 1] < hkey[c]:
            c += 1
        if hkey[c] >= k:
            break
        heap[i] = heap[c]
        hkey[i] = hkey[c]
        pos[heap[i]] = i
        i = c
    heap[i] = node
    hkey[i] = k
    pos[node] = i


@kernel
def push(heap: Any, hkey: FloatArray, pos: Any, size: int, u: int, k: float) -> int:
    """Queue ``u`` with key ``k`` (or move it up after its key fell to ``k``).

    Parameters
    ----------
    heap : ndarray of int32
        Node ids, a binary heap on ``hkey`` in its first ``size`` entries.
    hkey : ndarray of float
        The keys of ``heap``'s entries, index for index.
    pos : ndarray of int32
        Each node's index in ``heap`` (-1 never queued or free to queue again, -2 settled).
    size : int
        The heap's size.
    u : int
        The node.
    k : float
        Its key (not above its current key when already queued).

    Returns
    -------
    int
        The new heap size.
    """
    i = pos[u]
    if i < 0:
        i = size
        size += 1
    _sift_up(heap, hkey, pos, i, u, k)
    return size


@kernel
def pop(heap: Any, hkey: FloatArray, pos: Any, size: int, mark: int) -> int:
    """Remove the root ``heap[0]``; the last entry moves to the root and sifts down.

    Parameters
    ----------
    heap : ndarray of int32
        Node ids, a binary heap on ``hkey`` in its first ``size`` entries.
    hkey : ndarray of float
        The keys of ``heap``'s entries, index for index.
    pos : ndarray of int32
        Each node's index in ``heap`` (-1 never queued or free to queue again, -2 settled).
    size : int
        The heap's size.
    mark : int
        The root's new ``pos``: -2 settled, -1 free to queue again.

    Returns
    -------
    int
        The new heap size.
    """
    pos[heap[0]] = mark
    size -= 1
    if size > 0:
        heap[0] = heap[size]
        hkey[0] = hkey[size]
        _sift_down(heap, hkey, pos, size)
    return size
