"""Yos per surfacing cycle with ``surface_every_s``: the planner, the flight and the Slocum files count the same.

The planner counted ``ceil(surface_every_s / yo_s)`` yos per cycle, the flight surfaced at the first yo top after
``surface_every_s`` underwater, the first dive from the surface included: when ``surface_every_s`` was just above a
whole number k of yos (less than the first dive's ``climb_depth_m / |w_dive|`` above it) the planner, and with it
``yo10.ma``'s ``num_half_cycles_to_do``, said k + 1 yos and the flight flew k.  A Slocum flies the count its yo file
says, so there is one rule (:func:`auvplan.vehicles.glider.yos_per_cycle`: the first top at or after
``surface_every_s``, the first dive included, 1 to ``yos``), which the planner's cycle, the flight and the files use.

The oracle is worked out by hand from the yo's timing: leaving the surface, the top of yo j is reached at
T_j = climb_depth_m / |w_dive| + j (dive_s + climb_s), the first dive being 55 s (200 m yos) and 80 s (350 m) long.
``surface_every_s`` at k whole yos less 1 s, at k yos and 1 s above all lie before T_k: k yos; at T_k less 1 s and at
T_k: k yos; at T_k + 1 s: k + 1 yos.  The files are read with test_glider_exports' own parser and the flight's yos
counted from its track (bottom inflections between the first two fixes).
"""

from __future__ import annotations

import numpy as np
import pytest
from test_glider_exports import _ma

from auvplan.app.glider import _yo_glider
from auvplan.io.missions.glider import slocum_files
from auvplan.planners.timeopt.glider import cycle
from auvplan.sim.glider import fly_glider
from auvplan.vehicles.glider import GliderParams, yo_timing, yos_per_cycle
from auvplan.world import Bounds, World
from auvplan.world.currents.fields import UniformCurrent

BOX = Bounds(-60000.0, 60000.0, -60000.0, 60000.0, -1000.0, 0.0)
PTS = np.array([[0.0, 0.0], [6000.0, 2000.0], [12000.0, -1000.0]])

# (surface_every_s as whole yos + the first dive's share + seconds, the yos expected) for k = 1, 2
CASES = [(whole, first, sec, want) for whole in (1, 2) for first, sec, want in (
    (0, -1.0, whole), (0, 0.0, whole), (0, 1.0, whole),  # at whole yos: the first dive not yet flown
    (1, -1.0, whole), (1, 0.0, whole), (1, 1.0, whole + 1))]  # at the top of yo k, first dive included


def _glider(deep: bool, every: float = 0.0) -> GliderParams:
    if deep:  # a non-default yo: other depths, other speeds, a longer first dive
        return GliderParams(yos=9, dive_depth_m=350.0, climb_depth_m=15.0, surface_every_s=every)
    return GliderParams(yos=9, surface_every_s=every)


def _flown_yos(g: GliderParams, c_duration: float) -> int:
    """Bottom inflections the flight makes before its second fix (the first is at the start)."""
    w = World(BOX, currents=UniformCurrent((0.05, -0.02, 0.0)))
    tr = fly_glider(w, g, (0.0, 0.0), [(0.0, 50000.0)], 0.0, dt=5.0, max_s=c_duration + 3000.0)
    assert len(tr.fixes) >= 2
    before = tr.t[1:] <= tr.fixes[1, 0]
    return int(np.sum((tr.phase[:-1] == -1) & (tr.phase[1:] == 1) & before))


@pytest.mark.parametrize("deep", [False, True], ids=["200m", "350m"])
@pytest.mark.parametrize(("whole", "first", "sec", "want"), CASES,
                         ids=[f"{w}yo{'+dive' if f else ''}{s:+.0f}s" for w, f, s, _ in CASES])
def test_planner_flight_and_files_count_the_same_yos_at_the_boundary(deep, whole, first, sec, want):
    base = _glider(deep)
    yo = yo_timing(base, base.climb_depth_m, base.dive_depth_m)
    first_s = base.climb_depth_m / -yo.w_dive
    assert 50.0 < first_s < 100.0  # the first dive is far longer than the 1 s steps: the cases lie as described
    every = whole * (yo.dive_s + yo.climb_s) + first * first_s + sec
    g = _glider(deep, every)
    c = cycle(g)
    assert yos_per_cycle(g, yo) == want
    assert c.yos == want  # the planner (was ceil(every / yo_s): whole + 1 at "k yos + 1 s" and "T_k - 1 s")
    top = g.climb_depth_m
    assert c.underwater_s == pytest.approx(top / -yo.w_dive + want * (yo.dive_s + yo.climb_s) + top / yo.w_climb)
    assert c.underwater_s - top / yo.w_climb >= every - 1e-6  # it surfaces at a top at or after every ...
    assert c.underwater_s - top / yo.w_climb - (yo.dive_s + yo.climb_s) < every  # ... the first one
    files = slocum_files(PTS, (67.25, 13.75), g, 12.0, yos=c.yos, underwater_s=c.underwater_s)
    assert _ma(files["yo10.ma"])[1]["num_half_cycles_to_do"][1] == 2 * want  # what the Slocum flies
    assert _flown_yos(g, c.duration_s) == want  # the flight


def test_the_yos_cap_and_at_least_one():
    g = GliderParams(yos=2, surface_every_s=20000.0)
    yo = yo_timing(g, g.climb_depth_m, g.dive_depth_m)
    assert yos_per_cycle(g, yo) == 2 == cycle(g).yos
    assert yos_per_cycle(GliderParams(yos=4, surface_every_s=10.0), yo) == 1
    for every in (0.5, 1.0):  # a second or less ("surface every yo"): the first top, still one yo (mutants24)
        g = GliderParams(yos=4, surface_every_s=every)
        assert yos_per_cycle(g, yo) == 1 == cycle(g).yos
    assert yos_per_cycle(GliderParams(yos=4), yo) == 4


def test_the_files_need_the_planned_yos_with_surface_every_s():
    """With surface_every_s the yo file's count is the planned cycle's, never the glider's ``yos`` by default."""
    g = GliderParams(yos=9, surface_every_s=2300.0)
    with pytest.raises(ValueError, match="yos"):
        slocum_files(PTS, (67.25, 13.75), g, 12.0, underwater_s=cycle(g).underwater_s)


def test_mission_check_flies_the_yo_files_count():
    """``mission check`` flies ``num_half_cycles_to_do`` as the Slocum does, not the scenario's surface_every_s."""
    g = GliderParams(yos=9, surface_every_s=2300.0)  # 2300 s: one yo (its top at 2309 s)
    flown, why = _yo_glider(g, {"num_half_cycles_to_do": 4.0, "d_target_depth": 200.0}, 1000.0, "yo10.ma")
    assert not why
    assert yos_per_cycle(flown, yo_timing(flown, flown.climb_depth_m, flown.dive_depth_m)) == 2
    assert _flown_yos(flown, cycle(flown).duration_s) == 2
