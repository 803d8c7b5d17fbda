"""The indexed binary heap of the lattice search (compiled): ``int32`` node ids, keys in a separate array.

``heap`` holds node ids ordered by ``key``; ``pos[u]`` is ``u``'s index in it (-1 never queued or free
to queue again, -2 settled), so a node's key can fall and the node move up in place (decrease-key).
"""

from __future__ import annotations

from typing import Any

from ..._jit import kernel
from ..._types import FloatArray

__all__ = ["push", "pop"]


@kernel
def _sift_up(heap: Any, pos: Any, key: FloatArray, i: int) -> None:
    node = heap[i]
    while i > 0:
        parent = (i - 1) >> 1
        if key[heap[parent]] <= key[node]:
            break
        heap[i] = heap[parent]
        pos[heap[i]] = i
        i = parent
    heap[i] = node
    pos[node] = i


@kernel
def _sift_down(heap: Any, pos: Any, key: FloatArray, i: int, size: int) -> None:
    node = heap[i]
    while True:
        c = 2 * i + 1
        if c >= size:
            break
        if c + 1 < size and key[heap[c + 1]] < key[heap[c]]:
            c += 1
        if key[heap[c]] >= key[node]:
            break
        heap[i] = heap[c]
        pos[heap[i]] = i
        i = c
    heap[i] = node
    pos[node] = i


@kernel
def push(heap: Any, pos: Any, key: FloatArray, size: int, u: int) -> int:
    """Queue ``u`` (or move it up after its key fell).

    Parameters
    ----------
    heap : ndarray of int32
        Node ids, a binary heap on ``key`` in its first ``size`` entries.
    pos : ndarray of int32
        Each node's index in ``heap`` (-1 never queued or free to queue again, -2 settled).
    key : ndarray of float
        Each node's key.
    size : int
        The heap's size.
    u : int
        The node.

    Returns
    -------
    int
        The new heap size.
    """
    if pos[u] == -1:
        heap[size] = u
        pos[u] = size
        size += 1
    _sift_up(heap, pos, key, pos[u])
    return size


@kernel
def pop(heap: Any, pos: Any, key: FloatArray, size: int, mark: int) -> int:
    """Remove the root ``heap[0]``; the last entry moves to the root and sifts down.

    Parameters
    ----------
    heap : ndarray of int32
        Node ids, a binary heap on ``key`` in its first ``size`` entries.
    pos : ndarray of int32
        Each node's index in ``heap`` (-1 never queued or free to queue again, -2 settled).
    key : ndarray of float
        Each node's key.
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
        pos[heap[0]] = 0
        _sift_down(heap, pos, key, 0, size)
    return size
