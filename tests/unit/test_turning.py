"""Issue #36 point 4: CTRV prediction of turning movers (guidance/avoidance/turning.py), the time-windowed velocity
obstacles (guidance/avoidance/vo.py) and the brute-force avoidability oracle (guidance/avoidance/oracle.py)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from auvplan.guidance.avoidance.oracle import best_constant_manoeuvre
from auvplan.guidance.avoidance.turning import arc_chords, ctrv_position, turn_rate
from auvplan.guidance.avoidance.vo import (
    CFG,
    predicted_preference,
    predicted_preference_windows,
    vo_choose,
    vo_choose_windows,
)
from auvplan.vehicles import VehicleParams, VehicleState
from auvplan.world import Bounds, CircleMotion, LinearMotion, MovingObstacle, Sphere, WaypointMotion, World
from helpers import no_seabed

ORBIT = CircleMotion((100.0, 200.0, -50.0), 80.0, 2 * math.pi * 80.0 / 2.9, 0.3)  # 2.9 m/s, counter-clockwise


def _track(motion, t_end: float, window: float = 12.0) -> list[tuple[float, np.ndarray]]:
    return [(float(t), np.asarray(motion.position(t))) for t in np.arange(t_end - window, t_end + 1e-9, 1.0)]


def _velocity(motion, t: float, h: float = 1e-4) -> np.ndarray:
    return (np.asarray(motion.position(t + h)) - np.asarray(motion.position(t - h))) / (2 * h)


def test_ctrv_track_is_predicted_exactly():
    """An orbit (counter-clockwise: compass turn rate −2π/period) seen for 12 s: the fitted turn rate is
    the orbit's, and the CTRV prediction from its centre and velocity now is the orbit 0–120 s ahead."""
    t = 500.0
    omega = turn_rate(_track(ORBIT, t), t)
    assert omega == pytest.approx(-2 * math.pi / ORBIT.period, rel=1e-9)
    s = np.linspace(0.0, 120.0, 25)
    pred = ctrv_position(ORBIT.position(t), _velocity(ORBIT, t), omega, s)
    assert np.allclose(pred, ORBIT.position(t + s), atol=1e-4)
    # a clockwise orbit turns the other way
    cw = replace(ORBIT, period=-ORBIT.period)
    assert turn_rate(_track(cw, t), t) == pytest.approx(2 * math.pi / ORBIT.period, rel=1e-9)


def test_straight_mover_and_shuttle_turnaround_are_not_ctrv():
    """A straight mover has no turn rate; a shuttle reversing inside the window (its chord headings jump by
    π) is not a CTRV track — the sweep images handle it; after the turnaround it is straight again."""
    lin = LinearMotion((0.0, 0.0, -50.0), (2.0, 1.0, 0.0))
    assert turn_rate(_track(lin, 100.0), 100.0) == 0.0
    shuttle = WaypointMotion(np.array([[0.0, 50.0, -100.0], [300.0, 50.0, -100.0]]), 2.5, True)
    assert turn_rate(_track(shuttle, 125.0), 125.0) == 0.0  # turns at x = 300 m, t = 120 s
    assert turn_rate(_track(shuttle, 140.0), 140.0) == 0.0
    assert turn_rate(_track(shuttle, 140.0)[:3], 140.0) == 0.0  # too short


def test_arc_chords_hold_the_arc_within_their_windows():
    """Every point of the CTRV arc lies inside the chord of its time window (radius grown by the sagitta and
    the uncertainty), the grown radius increases with the time ahead, and the chords tile [0, horizon]."""
    t = 200.0
    c, v = np.asarray(ORBIT.position(t)), _velocity(ORBIT, t)
    omega = -2 * math.pi / ORBIT.period
    C, V, R, W = arc_chords(c, v, 20.0, omega, 120.0, piece=10.0, growth=0.05)
    assert W.shape == (12, 2) and W[0, 0] == 0.0 and W[-1, 1] == pytest.approx(120.0)
    assert np.allclose(W[1:, 0], W[:-1, 1]) and np.all(np.diff(R) > 0)
    for k in range(len(W)):
        s = np.linspace(W[k, 0], W[k, 1], 41)
        gap = np.linalg.norm(ORBIT.position(t + s) - (C[k] + V[k] * s[:, None]), axis=1)
        sag = 80.0 * (1 - math.cos(0.5 * omega * 10.0))
        assert gap.max() <= sag + 1e-6 and R[k] == pytest.approx(20.0 + sag + 0.05 * W[k, 1])


def _cfg(horizon: float = 60.0) -> np.ndarray:
    cfg = np.zeros(len(CFG))
    cfg[1], cfg[3] = 1.5, 1.5
    cfg[5:12] = (0.1, 2.0, horizon, 5.0, -1e9, 1e9, 0.0)
    return cfg


def test_windowed_velocity_obstacles():
    """Windows [0, inf] give the plain kernels' answers; an obstacle sitting on the vehicle's track is only
    seen while its window is open: a window closed before the vehicle gets there leaves the track clear."""
    p, v = np.zeros(3), np.array([0.0, 1.5, 0.0])
    C, V, R = np.array([[0.0, 60.0, 0.0]]), np.zeros((1, 3)), np.array([10.0])
    H, P, S = np.radians(np.arange(-90.0, 91.0, 10.0)), np.array([0.0]), np.array([1.5])
    pref, coef, wts = np.array([0.0, 1.0, 0.0]), no_seabed(), np.array([0.5, 0.3, 0.15, 0.3, 0.6])
    open_w = np.array([[0.0, math.inf]])
    assert vo_choose(p, v, np.zeros(3), C, V, R, H, P, S, pref, coef, _cfg(), wts) == \
        vo_choose_windows(p, v, np.zeros(3), C, V, R, open_w, H, P, S, pref, coef, _cfg(), wts)
    a = predicted_preference(p, v, C, V, R, pref, 60.0, 100.0, 1.0, 30.0)
    assert np.allclose(a, predicted_preference_windows(p, v, C, V, R, open_w, pref, 60.0, 100.0, 1.0, 30.0))
    ahead = np.array([0.0])
    _, _, _, clear, safe = vo_choose_windows(p, v, np.zeros(3), C, V, R, open_w, ahead, P, S, pref, coef, _cfg(), wts)
    assert not safe and clear < 0.0  # straight on runs into it at t ≈ 33 s
    early = np.array([[0.0, 20.0]])  # gone before the vehicle comes within 10 m (t ≈ 33 s)
    _, _, _, clear, safe = vo_choose_windows(p, v, np.zeros(3), C, V, R, early, ahead, P, S, pref, coef, _cfg(), wts)
    assert safe and clear == pytest.approx(60.0 - 1.5 * 20.0 - 10.0)
    beyond = np.array([[70.0, 90.0]])  # opens after the horizon
    _, _, _, clear, safe = vo_choose_windows(p, v, np.zeros(3), C, V, R, beyond, ahead, P, S, pref, coef, _cfg(), wts)
    assert safe and math.isinf(clear)
    assert np.allclose(predicted_preference_windows(p, v, C, V, R, beyond, pref, 60.0, 100.0, 1.0, 30.0), pref)


def test_oracle_finds_the_dodge_of_a_head_on_mover_and_none_when_boxed_in():
    """A 20 m sphere heading straight at the vehicle at 2 m/s from 150 m: holding the course meets it
    (clearance < 0), a turn away clears it; with a ring of movers converging on the vehicle nothing does."""
    vp = VehicleParams(speed=1.5)
    s0 = VehicleState(0.0, 0.0, -500.0, 0.0, 1.5)
    bounds = Bounds(-2000.0, 2000.0, -2000.0, 2000.0, -3000.0, 0.0)
    head_on = MovingObstacle(Sphere((0.0, 0.0, 0.0), 20.0), LinearMotion((0.0, 170.0, -500.0), (0.0, -2.0, 0.0)))
    w = World(bounds=bounds, moving=(head_on,))
    best = best_constant_manoeuvre(w, vp, s0, 0.0, horizon=120.0, margin=5.0, heading_step=30.0,
                                   pitch_fractions=(0.0,), speeds=(1.5,))
    assert best.safe > 0 and best.clearance >= 5.0 and best.candidates == 12
    straight = best_constant_manoeuvre(w, vp, s0, 0.0, horizon=120.0, heading_step=360.0, pitch_fractions=(0.0,),
                                       speeds=(1.5,))
    assert straight.candidates == 1 and straight.clearance < 0.0
    ring = tuple(MovingObstacle(Sphere((0.0, 0.0, 0.0), 30.0),
                                LinearMotion((100.0 * math.sin(a), 100.0 * math.cos(a), -500.0 + dz),
                                             (-3.0 * math.sin(a), -3.0 * math.cos(a), 0.0)))
                 for a in np.radians(np.arange(0.0, 360.0, 30.0)) for dz in (-40.0, 0.0, 40.0))
    boxed = best_constant_manoeuvre(replace(w, moving=ring), vp, s0, 0.0, horizon=60.0, heading_step=30.0)
    assert boxed.safe == 0 and boxed.clearance < 0.0
