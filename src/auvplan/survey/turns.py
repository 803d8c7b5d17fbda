"""Turns between survey lines the vehicle can fly: the shortest path of bounded curvature between the end
of one line and the start of the next (Dubins 1957; the six words LSL, RSR, LSR, RSL, RLR, LRL in the
closed forms of Shkel & Lumelsky 2001, "Classification of the Dubins set", Robotics and Autonomous
Systems 34).

Lines farther apart than ``2R`` are joined by a U-turn (arc, straight, arc: length ``πR + D - 2R`` between
parallel lines ``D`` apart); closer lines by an omega (keyhole) turn, a loop out and back (a CCC word or a
wide CSC), which Dubins' set also contains.  Angles here are mathematical (counter-clockwise from +x).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["Turn", "dubins", "sample_turn"]

_TWO_PI = 2.0 * math.pi


def _mod(a: float) -> float:
    return a % _TWO_PI


@dataclass(frozen=True)
class Turn:
    """A Dubins path: its word, its three segment lengths (normalised by the radius) and radius.

    Attributes
    ----------
    word : str
        ``"LSL"``, ``"RSR"``, ``"LSR"``, ``"RSL"``, ``"RLR"`` or ``"LRL"``.
    params : tuple of float
        Lengths of the three segments divided by ``radius`` (arc angles in rad for L and R).
    radius : float
        Turn radius (m).
    start : tuple of float
        ``(x, y, angle)`` of the start (m, rad counter-clockwise from +x).
    """

    word: str
    params: tuple[float, float, float]
    radius: float
    start: tuple[float, float, float]

    @property
    def length(self) -> float:
        """Length of the path (m)."""
        return self.radius * sum(self.params)


def _words(alpha: float, beta: float, d: float) -> dict[str, tuple[float, float, float]]:
    sa, sb, ca, cb = math.sin(alpha), math.sin(beta), math.cos(alpha), math.cos(beta)
    cab = math.cos(alpha - beta)
    out: dict[str, tuple[float, float, float]] = {}
    p2 = 2 + d * d - 2 * cab + 2 * d * (sa - sb)
    if p2 >= 0:
        t1 = math.atan2(cb - ca, d + sa - sb)
        out["LSL"] = (_mod(t1 - alpha), math.sqrt(p2), _mod(beta - t1))
    p2 = 2 + d * d - 2 * cab + 2 * d * (sb - sa)
    if p2 >= 0:
        t1 = math.atan2(ca - cb, d - sa + sb)
        out["RSR"] = (_mod(alpha - t1), math.sqrt(p2), _mod(t1 - beta))
    p2 = -2 + d * d + 2 * cab + 2 * d * (sa + sb)
    if p2 >= 0:
        p = math.sqrt(p2)
        t2 = math.atan2(-ca - cb, d + sa + sb) - math.atan2(-2.0, p)
        out["LSR"] = (_mod(t2 - alpha), p, _mod(t2 - _mod(beta)))
    p2 = -2 + d * d + 2 * cab - 2 * d * (sa + sb)
    if p2 >= 0:
        p = math.sqrt(p2)
        t2 = math.atan2(ca + cb, d - sa - sb) - math.atan2(2.0, p)
        out["RSL"] = (_mod(alpha - t2), p, _mod(beta - t2))
    tmp = (6.0 - d * d + 2 * cab + 2 * d * (sa - sb)) / 8.0
    if abs(tmp) <= 1:
        p = _mod(_TWO_PI - math.acos(tmp))
        t = _mod(alpha - math.atan2(ca - cb, d - sa + sb) + p / 2.0)
        out["RLR"] = (t, p, _mod(alpha - beta - t + p))
    tmp = (6.0 - d * d + 2 * cab + 2 * d * (sb - sa)) / 8.0
    if abs(tmp) <= 1:
        p = _mod(_TWO_PI - math.acos(tmp))
        t = _mod(-alpha - math.atan2(ca - cb, d + sa - sb) + p / 2.0)
        out["LRL"] = (t, p, _mod(_mod(beta) - alpha - t + p))
    return out


def dubins(start: tuple[float, float, float], end: tuple[float, float, float], radius: float) -> Turn:
    """The shortest path of curvature at most ``1/radius`` from ``start`` to ``end``.

    Parameters
    ----------
    start, end : tuple of float
        ``(x, y, angle)``: positions (m) and headings (rad counter-clockwise from +x).
    radius : float
        Least turn radius (m).

    Returns
    -------
    Turn
        The shortest of the six Dubins words.
    """
    if not radius > 0:
        raise ValueError(f"turn radius {radius}: must be positive")
    dx, dy = end[0] - start[0], end[1] - start[1]
    d = math.hypot(dx, dy) / radius
    theta = _mod(math.atan2(dy, dx))
    alpha, beta = _mod(start[2] - theta), _mod(end[2] - theta)
    words = _words(alpha, beta, d)
    word = min(words, key=lambda w: sum(words[w]))
    return Turn(word, words[word], radius, start)


def sample_turn(turn: Turn, step: float) -> NDArray[np.float64]:
    """Points along a Dubins path every ``step`` metres or less, both ends included.

    Parameters
    ----------
    turn : Turn
        The path.
    step : float
        Largest distance between points along the path (m).

    Returns
    -------
    numpy.ndarray
        ``(M, 3)`` points ``(x, y, angle)``.
    """
    x, y, th = turn.start
    r = turn.radius
    pts = [(x, y, th)]
    for kind, seg in zip(turn.word, turn.params, strict=True):
        n = 1 if kind == "S" else max(1, int(math.ceil(seg * r / step)))
        for i in range(1, n + 1):
            phi = seg * i / n
            if kind == "L":
                px, py, pt = x + r * (math.sin(th + phi) - math.sin(th)), y + r * (math.cos(th) - math.cos(th + phi)), \
                    th + phi
            elif kind == "R":
                px, py, pt = x + r * (math.sin(th) - math.sin(th - phi)), y + r * (math.cos(th - phi) - math.cos(th)), \
                    th - phi
            else:
                px, py, pt = x + r * phi * math.cos(th), y + r * phi * math.sin(th), th
            pts.append((px, py, pt))
        x, y, th = pts[-1]
    return np.asarray(pts)
