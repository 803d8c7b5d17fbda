"""The simulator's per-step arithmetic stays on Python floats (issue 35.3's regression, without timing).

A numpy scalar that enters the vehicle's state (the current or the wave noise as ``np.float64``) makes
every later operation of every step numpy-scalar arithmetic, several times slower than on floats, with
the same values: the 32 % slower simulator of the previous release.  These tests hold the types and,
as oracles, the values (the same formula on floats and on numpy scalars gives the same bits).
"""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.guidance.following.route import RouteTracker
from auvplan.vehicles import Vehicle, VehicleParams, VehicleState
from auvplan.world import UniformCurrent


def test_a_vehicle_step_with_numpy_current_and_noise_keeps_float_state_and_the_same_values():
    vp = VehicleParams(wave_sigma_r=0.01, wave_sigma_v=0.05)
    a, b = VehicleState(1.0, 2.0, -20.0, 0.3, 1.5), VehicleState(1.0, 2.0, -20.0, 0.3, 1.5)
    va, vb = Vehicle(vp, 0.1), Vehicle(vp, 0.1)
    rng = np.random.default_rng(3)
    for _ in range(50):
        noise, cur = rng.standard_normal(2), np.array([0.1, -0.3, 0.01])
        vel_a = va.step(a, 0.5, 0.0, 1.5, cur, noise)          # numpy inputs, as the simulator passes them
        vel_b = vb.step(b, 0.5, 0.0, 1.5, cur.tolist(), noise.tolist())  # plain floats
        assert vel_a == vel_b
    assert all(type(getattr(a, k)) is float for k in ("x", "y", "z", "psi", "r", "u", "v_wave", "r_wave"))
    assert (a.x, a.y, a.z, a.psi) == (b.x, b.y, b.z, b.psi)


def test_uniform_current_is_a_fresh_array_of_its_vector():
    c = UniformCurrent((0.2, -0.1, 0.0))
    v = c.velocity(np.zeros((4, 2, 3)))
    assert v.shape == (4, 2, 3) and v.flags.writeable and np.all(v == np.array([0.2, -0.1, 0.0]))
    v[0, 0, 0] = 9.0
    assert c.velocity(np.zeros((1, 3)))[0, 0] == 0.2  # no shared buffer between calls


def test_route_points_are_python_floats_with_the_geometry_of_the_leg():
    t = RouteTracker(np.array([[0.0, 0.0, -10.0], [100.0, 0.0, -30.0], [100.0, 50.0, -30.0]]), 5.0)
    rp = t.update(40.0, 3.0)
    assert (rp.leg, rp.along, rp.progress) == (0, 40.0, 40.0)
    assert rp.cross == pytest.approx(-3.0, abs=1e-12)  # course east: starboard is south
    assert rp.z_ref == -18.0 and rp.course == np.pi / 2 and rp.gamma == np.arctan2(-20.0, 100.0)
    assert all(type(v) is float for v in (rp.along, rp.cross, rp.course, rp.progress, rp.z_ref, rp.gamma))
    assert t.update(97.0, 0.0).leg == 1  # within the switch radius of the leg's end
