"""Document 001 compared like with like: the document's field as written beside the corrected one,
and LOS / ILOS / hybrid each with and without crab-angle current compensation (issue 24, item 4).

Oracles: eqs. 7–8 evaluated by hand; the invariant hybrid field = LOS on a straight leg with no
obstacle and the same compensation; LOS in a uniform cross current against its closed-form steady
state (e_ss = Δ tan(asin(c⊥/U)) without compensation; e = 0 and heading ψ_leg − asin(c⊥/U) with it).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from auvplan.errors import ScenarioError
from auvplan.guidance.following.hybrid import HybridGuidance, HybridParams, goal_factor, hybrid_force
from auvplan.guidance.following.los import LosGuidance, LosParams, los_heading
from auvplan.guidance.following.route import RouteTracker, crab_heading
from auvplan.io.scenario import loader as sc
from auvplan.sim import Mission, SimParams, simulate
from auvplan.vehicles import VehicleParams
from auvplan.world import Bounds, UniformCurrent, World

P_O = 25.0


# ---------------------------------------------------------------------- eqs. 7–8 by hand
@pytest.mark.parametrize("n", [1.0, 2.0])
@pytest.mark.parametrize("r_at", [5.0, 25.0, 80.0, 300.0])
def test_document_goal_factor_is_eqs_7_8_uncapped(n, r_at):
    """Eq. 8's factor r_at^n with the gain m = m_r P_o^(−n): (r_at/P_o)^n, above 1 beyond P_o; the
    corrected field caps it at 1."""
    doc = HybridParams(variant="document", influence=P_O, goal_power=n)
    cor = HybridParams(influence=P_O, goal_power=n)
    assert goal_factor(r_at, doc) == pytest.approx(r_at**n * P_O**-n, rel=1e-14)
    assert goal_factor(r_at, cor) == pytest.approx(min(r_at / P_O, 1.0) ** n, rel=1e-14)
    if r_at > P_O:
        assert goal_factor(r_at, doc) > 1.0 == goal_factor(r_at, cor)


@pytest.mark.parametrize("r_at", [10.0, 60.0, 300.0])
def test_document_field_is_eqs_3_to_8_with_no_lateral_bias(r_at):
    """Leg due north from (0, −100); vehicle at (3, 0) (3 m to starboard); obstacle to port at
    (−4, 6), its surface 5 m away.  Expected resultant: route attraction k_H·e towards the leg
    (eq. 3), heading attraction k_X·Δ along it (eq. 4), repulsion
    m (1/r_re − 1/P_o)(1/r_re²) r_at^n away from the obstacle (eq. 8, m = m_r P_o^(−n)) — and nothing
    else: the corrected field adds a bias along the normal."""
    m_r, n, d, e = 300.0, 1.0, 5.0, 3.0
    p = HybridParams(variant="document", k_route=1.2, k_heading=0.8, lookahead=15.0, influence=P_O,
                     k_repulse=m_r, goal_power=n)
    ox, oy = -4.0, 6.0
    f = hybrid_force(0.0, e, p, e, 0.0, [(ox, oy, d)], r_at, (0.0, -100.0))
    m = m_r * P_O**-n
    mag = m * (1.0 / d - 1.0 / P_O) * (1.0 / d**2) * r_at**n
    away = np.array([e - ox, 0.0 - oy]) / math.hypot(e - ox, oy)
    expected = np.array([-1.2 * e, 0.8 * 15.0]) + mag * away
    np.testing.assert_allclose(f, expected, rtol=1e-12, atol=1e-12)
    corrected = hybrid_force(0.0, e, replace(p, variant="corrected"), e, 0.0, [(ox, oy, d)], r_at, (0.0, -100.0))
    rho = min(r_at / P_O, 1.0)
    assert corrected[0] == pytest.approx(-1.2 * e + mag / r_at * P_O * rho * (away[0] + 2.0), rel=1e-12)


def test_variant_defaults_and_overrides():
    doc, cor = HybridParams(variant="document"), HybridParams()
    assert (doc.bias, doc.compensates) == (0.0, False)
    assert (cor.bias, cor.compensates) == (2.0, True)
    # set explicitly, the two keys apply to either variant (the comparison's axes)
    assert HybridParams(variant="document", current_compensation=True).compensates
    assert not HybridParams(current_compensation=False).compensates
    assert HybridParams(variant="document", lateral_bias=1.0).bias == 1.0
    # dataclasses.replace keeps "unset" unset: the variant's choice follows the variant
    assert replace(cor, variant="document").compensates is False
    with pytest.raises(ValueError, match="variant"):
        HybridParams(variant="literal")
    with pytest.raises(ValueError, match="lateral_bias"):
        HybridParams(lateral_bias=-1.0)
    assert LosParams().current_compensation is False


def test_scenario_keys_select_the_variant_and_the_compensation():
    base = sc.load("track-single")
    text = ('[mission]\nstart = [0.0, 0.0, -20.0]\ngoal = [600.0, 0.0, -20.0]\n'
            '[guidance.hybrid]\nvariant = "document"\n[guidance.los]\ncurrent_compensation = true\n')
    s = sc.loads(text, "doc.toml")
    assert s.guidance.hybrid.variant == "document" and not s.guidance.hybrid.compensates
    assert s.guidance.los.current_compensation is True
    assert base.guidance.hybrid.variant == "corrected" and base.guidance.hybrid.compensates
    with pytest.raises(ScenarioError, match=r"doc\.toml.*variant.*'paper'"):
        sc.loads(text.replace('"document"', '"paper"'), "doc.toml")
    with pytest.raises(ScenarioError, match=r"current_compensation"):
        sc.loads(text.replace("= true", '= "yes"'), "doc.toml")


# ---------------------------------------------------------------------- one command in a cross current
@pytest.mark.parametrize("cross", [-6.0, 0.0, 4.0])
def test_commands_with_and_without_crab_angle(cross):
    """Leg due east, current 0.3 m/s north (to port), U = 1.5 m/s: uncompensated laws fly LOS's angle
    as a heading; compensated ones fly crab_heading(LOS angle)."""
    cur, u = (0.0, 0.3, 0.0), 1.5
    y = -cross  # right of an eastbound leg is south
    los = los_heading(math.pi / 2, cross, 15.0)
    crabbed = crab_heading(los, cur, u)
    assert crabbed == pytest.approx(los + math.asin(0.3 * math.sin(los) / u), abs=1e-12)

    def cmd(g):
        return g.command(50.0, y, -20.0, cur, u, [], 0.1)[0]

    def route():
        return RouteTracker([[0, 0, -20], [1000, 0, -20]], 10.0)

    assert cmd(HybridGuidance(route(), HybridParams(variant="document"))) == pytest.approx(los, abs=1e-12)
    assert cmd(HybridGuidance(route(), HybridParams())) == pytest.approx(crabbed, abs=1e-12)
    assert cmd(LosGuidance(route(), LosParams())) == pytest.approx(los, abs=1e-12)
    assert cmd(LosGuidance(route(), LosParams(current_compensation=True))) == pytest.approx(crabbed, abs=1e-12)
    ilos = LosGuidance(route(), LosParams(current_compensation=True), integral=True)
    assert cmd(ilos) == pytest.approx(crabbed, abs=1e-12)  # integral state starts at 0


# ---------------------------------------------------------------------- closed loop
def _straight(current, waves: bool, length: float = 800.0):
    world = World(Bounds(-100, length + 100, -300, 300, -100, 0), currents=UniformCurrent(current))
    vp = VehicleParams(wave_sigma_r=0.01, wave_sigma_v=0.05) if waves else VehicleParams()
    mission = Mission("leg", (0, 0, -20), (length, 0, -20), route=((0, 0, -20), (length, 0, -20)), vehicle=vp,
                      sim=SimParams(arrival_radius=5.0))
    return world, mission


@pytest.mark.parametrize("compensate", [False, True])
def test_hybrid_field_equals_los_on_a_straight_leg_without_obstacles(compensate):
    """Invariant: no obstacle, k_H = k_X, same look-ahead and compensation ⇒ hybrid (either variant)
    and LOS fly the same track, step for step, in a cross current with waves."""
    world, m = _straight((0.05, 0.25, 0.0), waves=True)
    m = replace(m, los=LosParams(current_compensation=compensate))
    los = simulate(world, m, guidance="los", rng=3, avoidance="none")
    for variant in ("document", "corrected"):
        mh = replace(m, hybrid=HybridParams(variant=variant, current_compensation=compensate))
        hyb = simulate(world, mh, guidance="hybrid", rng=3, avoidance="none")
        assert hyb.status is los.status and hyb.t.size == los.t.size
        np.testing.assert_allclose(hyb.position, los.position, rtol=0, atol=1e-6)


@pytest.mark.parametrize("c_north", [0.3, -0.2])
def test_los_steady_state_in_a_uniform_cross_current(c_north):
    """Eastbound leg, current c north, no waves; c⊥ (to starboard) = −c.  Without compensation LOS
    settles where the drift stops, ė = U sin(ψ − ψ_leg) + c⊥ = 0 with ψ − ψ_leg = −atan(e/Δ):
    e_ss = Δ tan(asin(c⊥/U)), on the heading ψ_leg − asin(c⊥/U) — the crab angle, reached only by
    standing off the line.  With compensation the error → 0 on that same heading, and the speed made
    good is U cos β.  ILOS without compensation also ends on the line (its integral)."""
    U, D = 1.5, 15.0
    c_perp = -c_north
    world, m = _straight((0.0, c_north, 0.0), waves=False, length=1500.0)
    crab = math.pi / 2 - math.asin(c_perp / U)
    e_ss = D * math.tan(math.asin(c_perp / U))
    tail = slice(-1500, -100)  # the last ~140 s before arrival: 900 m of settling behind

    off = simulate(world, m, guidance="los", rng=0, avoidance="none")
    assert off.arrived
    np.testing.assert_allclose(off.cross_track[tail], e_ss, rtol=1e-4)
    np.testing.assert_allclose(off.heading[tail], crab, atol=1e-5)  # the same heading, reached off the line

    on = simulate(world, replace(m, los=LosParams(current_compensation=True)), guidance="los", rng=0,
                  avoidance="none")
    assert on.arrived
    assert np.abs(on.cross_track[tail]).max() < 1e-6
    np.testing.assert_allclose(on.heading[tail], crab, atol=1e-6)
    # ground speed along the leg: U cos β (the crab angle costs speed made good)
    np.testing.assert_allclose(on.speed[tail], U * math.cos(math.asin(c_perp / U)), rtol=1e-6)

    ilos = simulate(world, m, guidance="ilos", rng=0, avoidance="none")
    assert abs(ilos.cross_track[-100]) < 0.05 * abs(e_ss)


def test_uncapped_factor_closes_the_track_double_gap():
    """Why the document's field fails on ``track-double`` (README): 15 m before the gap between the
    obstacles at (300, ±10) (surfaces 14.53 m away, r_at = 315 m of a 600 m leg), the uncapped factor
    (12.6) makes the two repulsions' backward pull 2·m_r(1/d − 1/P_o)/d²·ρ·15/18.03 = 57.3 exceed the
    heading attraction k_X Δ = 15: the field points back (a local minimum before the gap).  Capped
    (ρ = 1) the pull is 4.5 and the field points on through; the two lateral biases cancel."""
    world, m = sc.build(sc.load("track-double"))
    obstacles = [(float(o.center[0]), float(o.center[1]), math.hypot(300.0 - 285.0, 10.0) - o.radius)
                 for o in world.obstacles]
    pull = [2 * 2.0e4 * (1 / obstacles[0][2] - 1 / P_O) / obstacles[0][2] ** 2 * rho * 15.0 / math.hypot(15.0, 10.0)
            for rho in (315.0 / P_O, 1.0)]
    for variant, expected in zip(("document", "corrected"), pull):
        p = HybridParams(variant=variant, current_compensation=False)
        fx, fy = hybrid_force(math.pi / 2, 0.0, p, 285.0, 0.0, obstacles, 315.0, (0.0, 0.0))
        assert fx == pytest.approx(15.0 - expected, rel=1e-12) and fy == pytest.approx(0.0, abs=1e-9)
    assert 15.0 - pull[0] < 0 < 15.0 - pull[1]
    assert pull[0] == pytest.approx(57.3, abs=0.05) and pull[1] == pytest.approx(4.55, abs=0.01)
