"""Closest approach and velocity obstacles for a turn-rate-limited vehicle (compiled kernels).

* **Closest approach** of an obstacle at relative position r = c − p moving with relative
  velocity w = v_o − v: t* = clip(−r·w / |w|², 0, T), d* = |r + w t*| − R (from its surface).
* **Velocity obstacle with the vehicle's limits**: a candidate command (heading ψ, pitch θ,
  speed u through the water) is not reached at once.  The heading turns at the steady yaw rate
  r_max = K δ_max of the Nomoto model, after the autopilot's lag: for τ = |Δψ| / r_max + lag the
  vehicle moves along the chord of its turn (mean velocity u sinc(Δψ/2) along ψ₀ + Δψ/2), then
  straight with u (cos θ sin ψ, cos θ cos ψ, sin θ) + current.  The candidate's clearance is the
  smallest distance, over both legs and the horizon T, between that track and every obstacle's
  predicted track, minus the obstacle's radius — exact for straight-moving obstacles, two
  closest-point-on-segment problems per obstacle.  The candidate's depth violation is how far
  its track leaves the depth band or comes below the seabed + altitude margin (sampled at the
  end of the turn and at half and full horizon).
* **Choice**: among candidates with clearance ≥ margin and no depth violation, the one whose
  direction through the water is closest in angle to the preferred direction (a heading, as the
  path follower's command, whose crab angle already accounts for the current), plus costs for changing
  speed, pitch and the previous choice (hysteresis) and for clearances below twice the margin;
  when none is safe, the candidate with the largest worst margin.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...runtime.jit import kernel
from ...world.terrain import elevation_kernel

__all__ = ["CFG", "closest_approach", "predicted_preference", "predicted_preference_windows", "vo_choose",
           "vo_choose_windows"]

_F64 = NDArray[np.float64]
"""Array of float64 (units as documented per parameter)."""


def closest_approach(rel_pos: ArrayLike, rel_vel: ArrayLike, radii: ArrayLike,
                     horizon: float) -> tuple[_F64, _F64]:
    """Return the time and surface distance of closest approach, both keeping their velocities.

    Parameters
    ----------
    rel_pos : array_like
        ``(M, 3)`` obstacle centre − vehicle position (m).
    rel_vel : array_like
        ``(M, 3)`` obstacle velocity − vehicle velocity (m/s).
    radii : array_like
        ``(M,)`` obstacle radii (m).
    horizon : float
        Look-ahead time T (s).

    Returns
    -------
    t : numpy.ndarray
        ``(M,)`` time of closest approach (s), within ``[0, horizon]``.
    distance : numpy.ndarray
        ``(M,)`` distance from the obstacle's surface then (m); negative inside.
    """
    r = np.asarray(rel_pos, dtype=float).reshape(-1, 3)
    w = np.asarray(rel_vel, dtype=float).reshape(-1, 3)
    ww = np.einsum("ij,ij->i", w, w)
    t = np.where(ww > 1e-12, -np.einsum("ij,ij->i", r, w) / np.maximum(ww, 1e-12), 0.0)
    t = np.clip(t, 0.0, horizon)
    d = np.linalg.norm(r + w * t[:, None], axis=1) - np.asarray(radii, dtype=float).reshape(-1)
    return t, d


@kernel(inline="always")
def _segment_min(rx: float, ry: float, rz: float, wx: float, wy: float, wz: float,
                 span: float) -> tuple[float, float]:
    """min over s ∈ [0, span] of |r + w s|, and that s."""
    ww = wx * wx + wy * wy + wz * wz
    s = 0.0
    if ww > 1e-12:
        s = min(max(-(rx * wx + ry * wy + rz * wz) / ww, 0.0), span)
    dx, dy, dz = rx + wx * s, ry + wy * s, rz + wz * s
    return math.sqrt(dx * dx + dy * dy + dz * dz), s


@kernel(inline="always")
def _window_min(rx: float, ry: float, rz: float, wx: float, wy: float, wz: float, lo: float,
                hi: float) -> tuple[float, float]:
    """min over s ∈ [lo, hi] of |r + w s| and that s; (inf, lo) when the window is empty."""
    if hi < lo:
        return math.inf, lo
    d, s = _segment_min(rx + wx * lo, ry + wy * lo, rz + wz * lo, wx, wy, wz, hi - lo)
    return d, lo + s


@kernel
def predicted_preference(p: _F64, v_now: _F64, C: _F64, V: _F64, R: _F64,
                         attraction: _F64, horizon: float, k_rep: float, w_obs: float,
                         radius: float) -> _F64:
    """Return the preferred direction: attraction plus repulsion from the obstacles' predicted positions.

    Every obstacle is valid over the whole horizon (windows [0, inf]; :func:`predicted_preference_windows`).

    Document 004's repulsion k₂ (1/d − 1/r) / d^w₂ from each obstacle's predicted position at closest
    approach (``d`` its predicted surface distance, only ≤ r repels), the vehicle keeping its
    velocity ``v_now``.

    Parameters
    ----------
    p : numpy.ndarray
        ``(3,)`` vehicle position (m).
    v_now : numpy.ndarray
        ``(3,)`` vehicle ground velocity (m/s).
    C : numpy.ndarray
        ``(M, 3)`` obstacle centres (m).
    V : numpy.ndarray
        ``(M, 3)`` obstacle velocities (m/s).
    R : numpy.ndarray
        ``(M,)`` obstacle radii (m).
    attraction : numpy.ndarray
        ``(3,)`` unit attraction direction.
    horizon : float
        Prediction horizon T (s).
    k_rep : float
        Repulsion gain k₂ (m^(w₂+1)).
    w_obs : float
        Distance exponent w₂.
    radius : float
        Influence radius r from the obstacle's surface (m).

    Returns
    -------
    numpy.ndarray
        ``(3,)`` unit direction; ``attraction`` when the sum vanishes.
    """
    W = np.empty((C.shape[0], 2))
    W[:, 0] = 0.0
    W[:, 1] = math.inf
    out: _F64 = predicted_preference_windows(p, v_now, C, V, R, W, attraction, horizon, k_rep, w_obs, radius)
    return out


@kernel
def predicted_preference_windows(p: _F64, v_now: _F64, C: _F64, V: _F64, R: _F64, W: _F64,
                                 attraction: _F64, horizon: float, k_rep: float, w_obs: float,
                                 radius: float) -> _F64:
    """Return the preferred direction: attraction plus repulsion from the obstacles' predicted positions.

    Document 004's repulsion k₂ (1/d − 1/r) / d^w₂ from each obstacle's predicted position at closest
    approach (``d`` its predicted surface distance, only ≤ r repels), the vehicle keeping its
    velocity ``v_now``.

    Parameters
    ----------
    p : numpy.ndarray
        ``(3,)`` vehicle position (m).
    v_now : numpy.ndarray
        ``(3,)`` vehicle ground velocity (m/s).
    C : numpy.ndarray
        ``(M, 3)`` obstacle centres (m).
    V : numpy.ndarray
        ``(M, 3)`` obstacle velocities (m/s).
    R : numpy.ndarray
        ``(M,)`` obstacle radii (m).
    W : numpy.ndarray
        ``(M, 2)`` time window [start, end] (s from now) in which each obstacle's ``C + V s`` holds
        (a chord of a turning mover's arc, :mod:`.turning`); [0, inf] for a straight mover.
    attraction : numpy.ndarray
        ``(3,)`` unit attraction direction.
    horizon : float
        Prediction horizon T (s).
    k_rep : float
        Repulsion gain k₂ (m^(w₂+1)).
    w_obs : float
        Distance exponent w₂.
    radius : float
        Influence radius r from the obstacle's surface (m).

    Returns
    -------
    numpy.ndarray
        ``(3,)`` unit direction; ``attraction`` when the sum vanishes.
    """
    f = attraction.copy()
    for m in range(C.shape[0]):
        rx, ry, rz = C[m, 0] - p[0], C[m, 1] - p[1], C[m, 2] - p[2]
        wx, wy, wz = V[m, 0] - v_now[0], V[m, 1] - v_now[1], V[m, 2] - v_now[2]
        dist, t = _window_min(rx, ry, rz, wx, wy, wz, W[m, 0], min(W[m, 1], horizon))
        d = dist - R[m]
        if d <= radius and dist > 1e-12:
            d = max(d, 1e-3)
            mag = k_rep * (1.0 / d - 1.0 / radius) / d**w_obs
            f[0] -= mag * (rx + wx * t) / dist
            f[1] -= mag * (ry + wy * t) / dist
            f[2] -= mag * (rz + wz * t) / dist
    n = math.sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2])
    return f / n if n > 1e-12 else attraction.copy()


@kernel(inline="always")
def _wrap(a: float) -> float:
    """Angle wrapped to [-π, π)."""
    return a - 2.0 * math.pi * math.floor((a + math.pi) / (2.0 * math.pi))


@kernel(inline="always")
def _outside(z: float, lo: float, hi: float) -> float:
    """How far (m) ``z`` is outside ``[lo, hi]``."""
    return max(0.0, lo - z, z - hi)


CFG = ("psi0", "u_now", "theta_pref", "u_cruise", "psi_last", "r_max", "lag", "horizon", "margin", "z_lo", "z_hi",
       "terrain", "x0", "y0", "dx", "dy", "altitude")
"""Order of the scalars in :func:`vo_choose`'s ``cfg`` array (``terrain`` 1.0 when ``coef`` is a seabed)."""


@kernel
def vo_choose(p: _F64, v_now: _F64, cur: _F64, C: _F64, V: _F64, R: _F64,
              headings: _F64, pitches: _F64, speeds: _F64, pref: _F64,
              coef: _F64, cfg: _F64, weights: _F64) -> tuple[int, int, int, float, bool]:
    """Choose the best candidate of ``headings × pitches × speeds`` under the vehicle's turn limits.

    Every obstacle is valid over the whole horizon (windows [0, inf]; :func:`vo_choose_windows`).

    Loops are flat (no array passed to a helper inside them): 500+ candidates must cost
    microseconds.

    Parameters
    ----------
    p : numpy.ndarray
        ``(3,)`` vehicle position (m).
    v_now : numpy.ndarray
        ``(3,)`` vehicle ground velocity (m/s); its vertical part is kept through the turn.
    cur : numpy.ndarray
        ``(3,)`` current velocity (m/s).
    C : numpy.ndarray
        ``(M, 3)`` obstacle centres (m).
    V : numpy.ndarray
        ``(M, 3)`` obstacle velocities (m/s).
    R : numpy.ndarray
        ``(M,)`` obstacle radii (m).
    headings : numpy.ndarray
        Candidate compass headings (rad).
    pitches : numpy.ndarray
        Candidate pitch angles (rad, up positive).
    speeds : numpy.ndarray
        Candidate speeds through the water (m/s).
    pref : numpy.ndarray
        ``(3,)`` unit preferred direction.
    coef : numpy.ndarray
        The seabed's bilinear coefficients (unused unless ``cfg``'s ``terrain`` is 1).
    cfg : numpy.ndarray
        The scalars named by :data:`CFG` (angles in rad, speeds in m/s, times in s, lengths in m).
    weights : numpy.ndarray
        Cost weights (speed, pitch, hysteresis, clearance, crossing ahead).

    Returns
    -------
    i, j, k : int
        Indices of the chosen heading, pitch and speed.
    clearance : float
        Its smallest predicted distance from an obstacle's surface over the horizon (m).
    safe : bool
        Whether it keeps the margin and the depth band; False: the least bad candidate.
    """
    W = np.empty((C.shape[0], 2))
    W[:, 0] = 0.0
    W[:, 1] = math.inf
    return vo_choose_windows(p, v_now, cur, C, V, R, W, headings, pitches, speeds, pref, coef, cfg, weights)


@kernel
def vo_choose_windows(p: _F64, v_now: _F64, cur: _F64, C: _F64, V: _F64, R: _F64, W: _F64,
                      headings: _F64, pitches: _F64, speeds: _F64, pref: _F64,
                      coef: _F64, cfg: _F64, weights: _F64) -> tuple[int, int, int, float, bool]:
    """Choose the best candidate of ``headings × pitches × speeds`` under the vehicle's turn limits.

    Loops are flat (no array passed to a helper inside them): 500+ candidates must cost
    microseconds.

    Parameters
    ----------
    p : numpy.ndarray
        ``(3,)`` vehicle position (m).
    v_now : numpy.ndarray
        ``(3,)`` vehicle ground velocity (m/s); its vertical part is kept through the turn.
    cur : numpy.ndarray
        ``(3,)`` current velocity (m/s).
    C : numpy.ndarray
        ``(M, 3)`` obstacle centres (m).
    V : numpy.ndarray
        ``(M, 3)`` obstacle velocities (m/s).
    R : numpy.ndarray
        ``(M,)`` obstacle radii (m).
    W : numpy.ndarray
        ``(M, 2)`` time window [start, end] (s from now) in which each obstacle's ``C + V s`` holds;
        [0, inf] for a straight mover.
    headings : numpy.ndarray
        Candidate compass headings (rad).
    pitches : numpy.ndarray
        Candidate pitch angles (rad, up positive).
    speeds : numpy.ndarray
        Candidate speeds through the water (m/s).
    pref : numpy.ndarray
        ``(3,)`` unit preferred direction.
    coef : numpy.ndarray
        The seabed's bilinear coefficients (unused unless ``cfg``'s ``terrain`` is 1).
    cfg : numpy.ndarray
        The scalars named by :data:`CFG` (angles in rad, speeds in m/s, times in s, lengths in m).
    weights : numpy.ndarray
        Cost weights (speed, pitch, hysteresis, clearance, crossing ahead).

    Returns
    -------
    i, j, k : int
        Indices of the chosen heading, pitch and speed.
    clearance : float
        Its smallest predicted distance from an obstacle's surface over the horizon (m).
    safe : bool
        Whether it keeps the margin and the depth band; False: the least bad candidate.
    """
    psi0, u_now, theta_pref, u_cruise, psi_last = cfg[0], cfg[1], cfg[2], cfg[3], cfg[4]
    r_max, lag, horizon, margin, z_lo, z_hi = cfg[5], cfg[6], cfg[7], cfg[8], cfg[9], cfg[10]
    terrain, x0, y0, gdx, gdy, altitude = cfg[11] > 0.0, cfg[12], cfg[13], cfg[14], cfg[15], cfg[16]
    bi, bj, bk, best_cost, best_clear = -1, 0, 0, math.inf, -math.inf
    fi, fj, fk, fall_score, fall_clear = 0, 0, 0, -math.inf, -math.inf
    cth, sth = np.cos(pitches), np.sin(pitches)
    M = C.shape[0]
    speed_o = np.empty(M)
    for m in range(M):
        speed_o[m] = math.sqrt(V[m, 0] ** 2 + V[m, 1] ** 2 + V[m, 2] ** 2)
    for i in range(headings.shape[0]):
        psi = headings[i]
        spsi, cpsi = math.sin(psi), math.cos(psi)
        d = _wrap(psi - psi0)
        tau = min(abs(d) / r_max + lag, horizon)
        half = 0.5 * d
        sinc = math.sin(half) / half if abs(half) > 1e-9 else 1.0
        v1x = u_now * sinc * math.sin(psi0 + half) + cur[0]
        v1y = u_now * sinc * math.cos(psi0 + half) + cur[1]
        v1z = v_now[2]
        tx, ty, tz = p[0] + v1x * tau, p[1] + v1y * tau, p[2] + v1z * tau
        lo = z_lo
        if terrain:
            lo = max(lo, elevation_kernel(coef, x0, y0, gdx, gdy, tx, ty) + altitude)
        viol_turn = _outside(tz, lo, z_hi)
        s_half, s_full = max(0.5 * horizon - tau, 0.0), max(horizon - tau, 0.0)
        base_cost = weights[2] * abs(_wrap(psi - psi_last))
        for j in range(pitches.shape[0]):
            # angle of the commanded direction through the water to the preferred one (the follower's
            # command is a heading too: its crab angle already accounts for the current)
            c = cth[j] * (spsi * pref[0] + cpsi * pref[1]) + sth[j] * pref[2]
            angle = math.acos(min(max(c, -1.0), 1.0)) + weights[1] * abs(pitches[j] - theta_pref)
            for k in range(speeds.shape[0]):
                u = speeds[k]
                vx = u * cth[j] * spsi + cur[0]
                vy = u * cth[j] * cpsi + cur[1]
                vz = u * sth[j] + cur[2]
                viol = viol_turn
                for s in (s_half, s_full):
                    x, y, z = tx + vx * s, ty + vy * s, tz + vz * s
                    lo = z_lo
                    if terrain:
                        lo = max(lo, elevation_kernel(coef, x0, y0, gdx, gdy, x, y) + altitude)
                    viol = max(viol, _outside(z, lo, z_hi))
                # clearance over the turn (v1 for tau s) and the straight leg (v), and whether the
                # vehicle then sits within 60° of a moving obstacle's bow (crossing ahead of it)
                clear = math.inf
                ahead = False
                for m in range(M):
                    rx, ry, rz = C[m, 0] - p[0], C[m, 1] - p[1], C[m, 2] - p[2]
                    w1x, w1y, w1z = V[m, 0] - v1x, V[m, 1] - v1y, V[m, 2] - v1z
                    d1, s1 = _window_min(rx, ry, rz, w1x, w1y, w1z, W[m, 0], min(W[m, 1], tau))
                    ex, ey, ez = rx + w1x * tau, ry + w1y * tau, rz + w1z * tau
                    w2x, w2y, w2z = V[m, 0] - vx, V[m, 1] - vy, V[m, 2] - vz
                    d2, s2 = _window_min(ex, ey, ez, w2x, w2y, w2z, max(W[m, 0] - tau, 0.0),
                                         min(W[m, 1], horizon) - tau)
                    if d1 < d2:
                        dm, qx, qy, qz = d1, rx + w1x * s1, ry + w1y * s1, rz + w1z * s1
                    else:
                        dm, qx, qy, qz = d2, ex + w2x * s2, ey + w2y * s2, ez + w2z * s2
                    if not math.isfinite(dm):
                        continue  # its window lies beyond the horizon
                    clear = min(clear, dm - R[m])
                    if speed_o[m] > 0.05 and -(qx * V[m, 0] + qy * V[m, 1] + qz * V[m, 2]) > 0.5 * speed_o[m] * dm:
                        ahead = True
                if viol <= 0.0 and clear >= margin:
                    cost = base_cost + angle + weights[0] * abs(u - u_cruise) / u_cruise
                    cost += weights[3] * max(0.0, 1.0 - clear / (2.0 * margin))
                    if ahead:
                        cost += weights[4]
                    if cost < best_cost:
                        bi, bj, bk, best_cost, best_clear = i, j, k, cost, clear
                else:
                    score = min(clear - margin, -viol)
                    if score > fall_score:
                        fi, fj, fk, fall_score, fall_clear = i, j, k, score, clear
    if bi >= 0:
        return bi, bj, bk, best_clear, True
    return fi, fj, fk, fall_clear, False
