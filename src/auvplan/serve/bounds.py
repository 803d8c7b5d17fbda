"""Bounds of what one request of ``auvplan serve`` may ask for, checked before any work.

A typed or dragged position must lie in the scenario's area (the world's bounds; depths within the
water column widened by its own height, so a waypoint above the surface is still checked and shown
as a violation): a waypoint 10⁹ m away is refused naming the waypoint instead of integrating the
energy along a 10⁹ m leg.  The whole mission's work — the energy integration in ``[endurance] ds_m``
steps and the check's legs — goes through the project's one estimator
(:func:`auvplan.io.files.limits.check_route_endurance`) before it is computed, where it is committed.
"""

from __future__ import annotations

import math
from typing import Any

from ..errors import AuvplanError
from ..world import World

__all__ = ["scalar", "inside_area"]


def scalar(value: Any, what: str) -> float:
    """A finite number sent by the page.

    Parameters
    ----------
    value : object
        The JSON value.
    what : str
        What it is, for the message (``move x``).

    Returns
    -------
    float
        The number.
    """
    if isinstance(value, bool) or not isinstance(value, int | float | str):
        raise AuvplanError(f"{what} = {str(value)[:40]!r}: not a number")
    try:
        v = float(value)
    except OverflowError:
        raise AuvplanError(f"{what} = {str(value)[:40]}: out of range") from None
    except ValueError:
        raise AuvplanError(f"{what} = {str(value)[:40]!r}: not a number") from None
    if not math.isfinite(v):
        raise AuvplanError(f"{what} = {v}: every coordinate must be a finite number")
    return v


def inside_area(world: World, op: str, index: int | None, xyz: list[float | None]) -> None:
    """Refuse a position outside the scenario's area, naming the waypoint, the value and the area.

    Parameters
    ----------
    world : World
        Its bounds.
    op : str
        The edit (``move``, ``insert``, ``depth``, ``delete``).
    index : int or None
        The waypoint (None for an insert).
    xyz : list of float or None
        The sent coordinates (None where not sent).
    """
    b = world.bounds
    dz = b.zmax - b.zmin
    spans = {"x": (b.xmin, b.xmax), "y": (b.ymin, b.ymax), "z": (b.zmin - dz, b.zmax + dz)}
    who = "the inserted waypoint" if index is None else f"waypoint {index}"
    for (k, (lo, hi)), v in zip(spans.items(), xyz, strict=True):
        if v is not None and not lo <= v <= hi:
            raise AuvplanError(f"{op}: {who} {k} = {v:.6g} m is outside the scenario's area ({k} from {lo:.0f} "
                               f"to {hi:.0f} m)")
