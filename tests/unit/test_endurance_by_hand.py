"""The energy budget's input checks and edge cases by hand (issue 49's mutation run of ``endurance``)."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.endurance.budget import traverse
from auvplan.world import Bounds, World

WORLD = World(Bounds(-1000, 1000, -1000, 1000, -200, 0))
PTS = np.array([[0.0, 0.0, -50.0], [100.0, 0.0, -50.0], [200.0, 0.0, -50.0]])


@pytest.mark.parametrize("speeds", [[1.0, 0.0], [0.0, 1.0], [1.0, -1.0], [1.0, np.nan], [1.0, np.inf]])
def test_traverse_refuses_any_leg_speed_that_is_not_positive_and_finite(speeds) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ValueError, match="leg speeds and ds must be positive"):
        traverse(WORLD, PTS, speeds, 0.0, 10.0)


def test_traverse_in_still_water_takes_length_over_speed_per_leg() -> None:
    tr = traverse(WORLD, PTS, [1.0, 2.0], 100.0, 10.0)
    assert tr.ok and tr.times.tolist() == pytest.approx([100.0, 200.0, 250.0])


def test_traverse_samples_the_current_at_each_steps_midpoint() -> None:
    """A following current growing linearly along the leg, u = 1e-3 x (m/s): the time over 0 <= x <= 200 m at
    V = 1 m/s is ∫ dx / (1 + 1e-3 x) = ln(1.2) / 1e-3 = 182.32 s (midpoint steps of 10 m: within 0.01 s)."""
    from auvplan.world import GriddedCurrent

    x = np.array([-1000.0, 1000.0])
    u = np.broadcast_to(1e-3 * x, (1, 2, 2)).copy()
    world = World(Bounds(-1000, 1000, -1000, 1000, -200, 0),
                  currents=GriddedCurrent(x, np.array([-1000.0, 1000.0]), np.array([0.0]), u, np.zeros_like(u)))
    tr = traverse(world, PTS[[0, 2]], 1.0, 0.0, 10.0)
    assert tr.times[-1] == pytest.approx(np.log(1.2) / 1e-3, abs=0.01)


def test_reserve_broken_names_the_leg_where_the_reserve_is_entered() -> None:
    """90 % usable, 20 % reserve: 70 % of the battery to spend.  Three 1 km legs at 1 m/s in still water, each
    (15 + 5.82) W × 1000 s = 5.78 Wh, the battery sized so that 2.5 legs use the 70 %: the reserve is entered on
    leg 2: the message says so; the point of no return of a mission that cannot come back from the start is
    INFEASIBLE and does not claim the whole mission."""
    from auvplan._types import Status
    from auvplan.endurance.budget import budget_of
    from auvplan.endurance.pnr import point_of_no_return
    from auvplan.endurance.power import EnergyModel

    pts = np.array([[0.0, 0.0, -50.0], [1000.0, 0.0, -50.0], [2000.0, 0.0, -50.0], [3000.0, 0.0, -50.0]])
    leg_wh = (15.0 + 5.82) * 1000.0 / 3600.0  # P(1 m/s) over 1000 s
    battery = 2.5 * leg_wh / 0.7  # 70 % of it is 2.5 legs: the reserve is entered half-way along leg 2
    model = EnergyModel(battery_wh=battery)
    tr = traverse(WORLD, pts, 1.0, 0.0, 100.0)
    b = budget_of(tr, model)
    assert b.status is Status.RESERVE_BROKEN and "the reserve is entered on leg 2" in b.message, b.message
    tiny = EnergyModel(battery_wh=0.5 * leg_wh)
    pnr = point_of_no_return(WORLD, tr, tiny, recovery=pts[-1])  # the boat waits 3 km away
    assert pnr.status is Status.INFEASIBLE and pnr.whole_mission is False and pnr.s_m == 0.0
