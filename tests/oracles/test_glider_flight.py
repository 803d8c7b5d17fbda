"""The glider flight model (issue 58) against analytic force balance and real Slocum dives.

Real data: tests/data/slocum_dives_2014_204.csv, cut by tools/cut_slocum_dives.py from the
amadeus and sebastian Slocum G2 files shipped in dbdreader 0.6.3's source distribution
(North Sea, 2014-07-23, one ~1 h segment of 0-40 m yos each).  The model is calibrated (neutral
density and C_D0) on the first half of each glider's legs and checked on the second half.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from auvplan.vehicles.glider import G, GliderParams, attack_angle, pitch_for_speed, steady_glide, yo_timing
from auvplan.vehicles.glider_fit import calibrate, dead_reckoned_current, yo_legs

DATA = Path(__file__).resolve().parents[1] / "data" / "slocum_dives_2014_204.csv"


def _columns(glider: str) -> dict[str, np.ndarray]:
    with DATA.open() as fh:
        rows = list(csv.reader(line for line in fh if not line.startswith("#")))
    head, body = rows[0], [r for r in rows[1:] if r[0] == glider]
    return {h: np.array([float(r[i]) if r[i] else math.nan for r in body]) for i, h in enumerate(head) if i}


def test_force_balance_holds():
    """Drag = F sin γ and lift = F cos γ at the solved glide, for dives and climbs (eqs. 1-7)."""
    p = GliderParams()
    th = np.radians([-40.0, -26.0, -15.0, 15.0, 26.0, 40.0])
    dv = np.array([-230.0, -230.0, -100.0, 100.0, 230.0, 230.0])
    gl = steady_glide(p, th, dv)
    fb = G * (1025.0 * (p.volume_m3 + 1e-6 * dv) - p.mass_kg)
    q = 0.5 * 1025.0 * p.wing_area_m2 * gl.speed**2
    drag = q * (p.cd0 + p.cd1 * gl.alpha**2)
    lift = q * (p.hull_lift + p.wing_lift) * gl.alpha
    np.testing.assert_allclose(drag, fb * np.sin(gl.gamma), rtol=1e-9)
    np.testing.assert_allclose(lift, fb * np.cos(gl.gamma), rtol=1e-9)
    np.testing.assert_allclose(np.hypot(gl.u, gl.w), gl.speed, rtol=1e-12)
    assert np.all(np.sign(gl.w) == np.sign(th)) and np.all(gl.u > 0)


def test_attack_angle_root_and_inverse():
    """α solves its equation; pitch_for_speed inverts steady_glide."""
    p = GliderParams()
    th = np.radians(np.linspace(10, 45, 8))
    a = attack_angle(th, p.cd0, p.cd1, p.hull_lift + p.wing_lift)
    lhs = p.cd0 + p.cd1 * a**2
    np.testing.assert_allclose(lhs, (p.hull_lift + p.wing_lift) * a * np.tan(th + a), rtol=1e-9)
    gl = steady_glide(p, -th, -230.0)
    np.testing.assert_allclose(pitch_for_speed(p, gl.w, -230.0), -th, atol=1e-9)


def test_yo_timing_adds_up():
    """Durations are depth span / vertical speed; the pump works against the bottom pressure."""
    p = GliderParams()
    yo = yo_timing(p, 10.0, 200.0)
    assert yo.dive_s == pytest.approx(190.0 / -yo.w_dive) and yo.climb_s == pytest.approx(190.0 / yo.w_climb)
    assert yo.pump_j == pytest.approx(1025.0 * G * 200.0 * 460e-6 / p.pump_efficiency)
    assert 0.2 < yo.speed < 0.4  # a Slocum's 0.25-0.4 m/s through the water


@pytest.mark.parametrize("glider", ["amadeus", "sebastian"])
def test_real_dives_within_ten_percent(glider):
    """Held-out legs: vertical speed, pitch (model inverted) and horizontal speed within 10 %."""
    c = _columns(glider)
    legs = yo_legs(c["t"], c["depth_m"], c["pitch_rad"], c["ballast_cc"])
    assert len(legs) >= 12  # 6+ dives and 6+ climbs of 35-40 m
    half = len(legs) // 2
    p = calibrate(GliderParams(), legs[:half])
    test = legs[half:]
    th = np.array([lg.pitch for lg in test])
    b = np.array([lg.ballast_cc for lg in test])
    pr = 1025.0 * G * np.array([lg.depth_m for lg in test])
    w = np.array([lg.w for lg in test])
    gl = steady_glide(p, th, b, 1025.0, pr)
    assert np.all(np.abs(gl.w / w - 1.0) < 0.10)
    assert np.all(np.abs(pitch_for_speed(p, w, b, 1025.0, pr) / th - 1.0) < 0.10)
    # horizontal speed: the measured vertical speed over the tangent of the measured glide angle
    u_meas = np.abs(w) / np.tan(np.abs(th + attack_angle(th, p.cd0, p.cd1, p.hull_lift + p.wing_lift)))
    assert np.all(np.abs(gl.u / u_meas - 1.0) < 0.10)


@pytest.mark.parametrize("glider", ["amadeus", "sebastian"])
def test_depth_averaged_current_matches_the_gliders_own(glider):
    """Fixes less the model's dead reckoning agree with m_water_vx/vy within 0.03 m/s."""
    c = _columns(glider)
    legs = yo_legs(c["t"], c["depth_m"], c["pitch_rad"], c["ballast_cc"])
    p = calibrate(GliderParams(), legs[: len(legs) // 2])
    under = np.flatnonzero(c["depth_m"] > 1.0)
    fixed = np.isfinite(c["lat"])
    f0 = np.flatnonzero(fixed[: under[0]])[-1]
    f1 = under[-1] + np.flatnonzero(fixed[under[-1]:])[0]
    k = slice(f0, f1 + 1)
    vx, vy = dead_reckoned_current(p, c["t"][k], c["depth_m"][k], c["pitch_rad"][k], c["ballast_cc"][k],
                                   c["heading_rad"][k], (c["lat"][f0], c["lon"][f0]), (c["lat"][f1], c["lon"][f1]))
    own = under[-1] + np.flatnonzero(np.isfinite(c["water_vx"][under[-1]:]))[0]  # its estimate after the segment
    ref = c["water_vx"][own], c["water_vy"][own]
    assert math.hypot(vx - ref[0], vy - ref[1]) < 0.03
