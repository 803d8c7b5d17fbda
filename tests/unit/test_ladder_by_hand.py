"""The ladder of lattices (``planners/grid/ladder.py``) by hand: which cells the rungs get, and which rung's
plan wins, with the rungs' lattice searches replaced by given screened and refined costs (issue 49.3).

The oracles are the module's stated rules: rungs double from the finest cell while the cell is under 1/25 of
the search box's narrower horizontal side; coarse to fine, a rung is refined to convergence only when its
screened cost is at most :data:`~auvplan.planners.grid.ladder.MARGIN` (relative) above the screened cost of
the best plan so far; the cheapest refined plan wins (the coarser on a tie); ``history`` is the best cost
after each rung; ``evaluations`` sums every lattice's edges; the message counts the screened and refined
lattice paths and names the winner; with no path, the finest rung's failure and the coarser cells tried.
Each test runs in milliseconds (no lattice is built).
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from auvplan._types import Status
from auvplan.planners import GridParams, PlannerSpec, PlanningProblem
from auvplan.planners.core.base import PlanResult
from auvplan.planners.core.common import search_box
from auvplan.planners.grid import ladder
from auvplan.world import Bounds, Margins, Terrain, World

PATH = np.array([[1000.0, 5000.0, -100.0], [9000.0, 5000.0, -100.0]])


def _world(x0: float, x1: float, y0: float, y1: float, depth: float = 300.0) -> World:
    t = Terrain(np.linspace(x0, x1, 11), np.linspace(y0, y1, 16), np.full((16, 11), -depth))
    return World(Bounds(x0, x1, y0, y1, -depth, 0.0), t, margins=Margins(min_altitude=5.0))


def _cells(cell: float, **kw) -> list[float]:  # type: ignore[no-untyped-def]
    """The rungs of a 10 km x 30 km box whose corner is not the origin (narrower side 10 km: top cell 400 m)."""
    w = _world(2000.0, 12000.0, -5000.0, 25000.0)
    prob = PlanningProblem(w, np.array([3000.0, 0.0, -100.0]), np.array([11000.0, 20000.0, -100.0]), 1.5)
    return ladder._cells(prob, GridParams(cell=cell, **kw), None)


@pytest.mark.parametrize(("cell", "rungs"), [
    (100.0, [100.0, 200.0, 400.0]),  # up to 10 km / 25 = 400 m
    (390.0, [390.0, 780.0]),  # 390 < 400 gets one coarser rung (at 1/26 of the side it would not)
    (400.0, [400.0]),  # at exactly 1/25 of the narrower side: no coarser rung
    (1000.0, [1000.0]),
])
def test_rungs_double_while_under_a_25th_of_the_narrower_side(cell, rungs) -> None:  # type: ignore[no-untyped-def]
    """Rungs of the cell and its doublings while under 1/25 of the narrower horizontal side of the search box
    (10 km of a 10 km x 30 km box at x 2-12 km, y -5-25 km; its 300 m depth band plays no part), finest first."""
    lower, upper = search_box(PlanningProblem(_world(2000.0, 12000.0, -5000.0, 25000.0), PATH[0], PATH[1], 1.5))
    assert (upper - lower)[:2].tolist() == [10000.0, 30000.0] and (upper - lower)[2] < 400.0
    assert _cells(cell) == rungs
    assert _cells(cell, cell_z=50.0) == rungs  # the horizontal cell, not the vertical one


def test_no_ladder_is_the_finest_rung_alone_and_a_given_lattice_sets_the_finest_cell() -> None:
    w = _world(2000.0, 12000.0, -5000.0, 25000.0)
    prob = PlanningProblem(w, np.array([3000.0, 0.0, -100.0]), np.array([11000.0, 20000.0, -100.0]), 1.5)
    assert ladder._cells(prob, GridParams(cell=100.0, ladder=False), None) == [100.0]
    given = SimpleNamespace(cell=150.0)  # a GridReference's cell (the lattice re-used for the finest rung)
    assert ladder._cells(prob, GridParams(cell=100.0), given) == [150.0, 300.0, 600.0]  # type: ignore[arg-type]


# ---------------------------------------------------------------------- which rung wins: the searches given
class _Rungs:
    """Stand-ins for a rung's two lattice searches and refinements: per (cell, links) a screened cost and a
    refined cost (None: no lattice path of that kind; a refined cost of None: the refined plan fails the
    exact segment test); ``edges[cell]`` the rung's lattice edges.  Records each rung's call."""

    def __init__(self, screened: dict, refined: dict, edges: dict, why: str = "") -> None:  # type: ignore[type-arg]
        self.screened, self.refined, self.edges, self.why = screened, refined, edges, why
        self.calls: list[tuple[float, object]] = []

    def screen(self, problem, spec, model, rung, reference):  # type: ignore[no-untyped-def]
        self.calls.append((rung.cell, reference))
        cands = [(c, links, PATH, (rung.cell, links)) for (cell, links), c in self.screened.items()
                 if cell == rung.cell and c is not None]
        return cands, self.edges.get(rung.cell, 0), f"{self.why} at {rung.cell:g} m" if self.why else ""

    def finish(self, problem, spec, path, ref, levels, t0):  # type: ignore[no-untyped-def]
        cost = self.refined[ref]
        status = Status.EXACT if cost is not None else Status.INFEASIBLE
        return PlanResult(status, path, cost if cost is not None else float("inf"), {}, 7, 1, 0.0, np.empty(0), "grid",
                          message=f"plan of {ref[0]:g} m / {ref[1]}" + ("" if cost is not None else " failed"))


@pytest.fixture
def rungs(monkeypatch):  # type: ignore[no-untyped-def]
    def make(screened, refined, edges, why=""):  # type: ignore[no-untyped-def]
        r = _Rungs(screened, refined, edges, why)
        monkeypatch.setattr(ladder, "_screened", r.screen)
        monkeypatch.setattr(ladder, "_finish", r.finish)
        monkeypatch.setattr(ladder, "_converge", lambda problem, spec, raw, model, it, tol: (raw, None, 3))
        return r
    return make


def _plan(cell: float = 100.0, reference: object = None, **kw) -> PlanResult:  # type: ignore[no-untyped-def]
    """The ladder over a 10 km square (rungs 100, 200, 400 m from a 100 m cell)."""
    w = _world(0.0, 10000.0, 0.0, 10000.0)
    spec = PlannerSpec(name="grid", grid=GridParams(objective="length", cell=cell, **kw))
    return ladder.plan_ladder(PlanningProblem(w, PATH[0], PATH[1], 1.5), spec, reference)  # type: ignore[arg-type]


def test_a_rung_within_the_margin_is_refined_and_one_above_it_is_skipped(rungs) -> None:  # type: ignore[no-untyped-def]
    """Coarse to fine: 400 m (any-angle paths screen cheaper: 990 against 1000) refines to 980; 200 m screens
    5e-4 above 990 (over MARGIN = 2e-4): skipped although its refinement would win; 100 m screens 1e-4 above:
    refined to 975, the winner.  Six lattice paths screened, two refined; the edges of every lattice summed."""
    r = rungs({(400.0, 0): 1000.0, (400.0, 16): 990.0, (200.0, 0): 990.0 * (1 + 5e-4), (200.0, 16): 2000.0,
               (100.0, 0): 990.0 * (1 + 1e-4), (100.0, 16): 1500.0},
              {(400.0, 16): 980.0, (200.0, 0): 900.0, (100.0, 0): 975.0}, {400.0: 30, 200.0: 200, 100.0: 1000})
    given = SimpleNamespace(cell=100.0)
    res = _plan(reference=given)
    assert [c for c, _ in r.calls] == [400.0, 200.0, 100.0]
    assert [ref is given for _, ref in r.calls] == [False, False, True]  # the given lattice: the finest rung's
    assert res.status is Status.EXACT and res.cost == 975.0 and res.evaluations == 1230
    assert res.history.tolist() == [980.0, 980.0, 975.0]
    assert res.message == ("plan of 100 m / 0; best of the lattices at 100, 200, 400 m: 100 m, 26 directions "
                           "(6 lattice paths screened, 2 refined to convergence)")
    assert 0.0 <= res.wall_time_s < 60.0


def test_a_rung_screened_exactly_at_the_margin_is_refined(rungs) -> None:  # type: ignore[no-untyped-def]
    """At most MARGIN above is refined: 5001 against 5000 (5000 + 2e-4 x 5000 exactly in floats)."""
    assert 5000.0 + ladder.MARGIN * 5000.0 == 5001.0 and 5001.0 - 5000.0 == ladder.MARGIN * 5000.0
    r = rungs({(400.0, 16): 5000.0, (200.0, 16): 5001.0, (100.0, 16): 5000.0 * 1.01},
              {(400.0, 16): 4990.0, (200.0, 16): 4980.0, (100.0, 16): 1.0}, {})
    res = _plan()
    assert res.cost == 4980.0 and res.history.tolist() == [4990.0, 4980.0, 4980.0]
    assert res.message.endswith("200 m, any-angle links of 16 cells (3 lattice paths screened, 2 refined to "
                                "convergence)")
    assert len(r.calls) == 3


def test_the_coarser_rung_wins_a_tie_and_a_rung_without_a_path_is_passed(rungs) -> None:  # type: ignore[no-untyped-def]
    """400 m has no lattice path (history inf); 200 m and 100 m refine to the same cost: the coarser wins."""
    rungs({(200.0, 0): 500.0, (100.0, 0): 500.0}, {(200.0, 0): 480.0, (100.0, 0): 480.0}, {})
    res = _plan()
    assert res.history.tolist() == [float("inf"), 480.0, 480.0]
    assert res.message.startswith("plan of 200 m / 0;") and "2 lattice paths screened, 2 refined" in res.message


def test_a_failed_refinement_does_not_win_and_the_finer_rung_does(rungs) -> None:  # type: ignore[no-untyped-def]
    rungs({(400.0, 0): 100.0, (200.0, 0): 100.0, (100.0, 0): 100.0},
          {(400.0, 0): None, (200.0, 0): 90.0, (100.0, 0): 95.0}, {})
    res = _plan()
    assert res.status is Status.EXACT and res.cost == 90.0 and res.history.tolist() == [float("inf"), 90.0, 90.0]
    assert res.message.startswith("plan of 200 m / 0;") and "3 refined" in res.message


def test_when_every_refinement_fails_the_first_failure_is_the_result(rungs) -> None:  # type: ignore[no-untyped-def]
    """No rung's refined plan passes: the coarsest failure is returned, with every lattice's edges."""
    rungs({(400.0, 0): 100.0, (200.0, 0): 100.0, (100.0, 0): 100.0}, dict.fromkeys(
        [(400.0, 0), (200.0, 0), (100.0, 0)]), {400.0: 1, 200.0: 10, 100.0: 100})
    res = _plan()
    assert res.status is Status.INFEASIBLE and res.message == "plan of 400 m / 0 failed" and res.evaluations == 111


def test_no_lattice_path_on_any_rung_names_the_finest_failure_and_the_coarser_cells(rungs) -> None:  # type: ignore[no-untyped-def]
    rungs({}, {}, {400.0: 1, 200.0: 10, 100.0: 100}, why="no free path")
    res = _plan()
    assert res.status is Status.INFEASIBLE and res.path.shape == (0, 3) and res.cost == float("inf")
    assert res.message == "no free path at 100 m; no path on the coarser lattices either (200, 400 m)"
    one = _plan(ladder=False)  # one rung: nothing coarser to name
    assert one.status is Status.INFEASIBLE and one.message == "no free path at 100 m"
    two = _plan(cell=200.0)  # rungs 200 and 400 m
    assert two.message == "no free path at 200 m; no path on the coarser lattices either (400 m)"


def test_a_single_rung_ladder_is_that_rungs_plan(rungs) -> None:  # type: ignore[no-untyped-def]
    rungs({(100.0, 0): 50.0, (100.0, 16): 40.0}, {(100.0, 16): 45.0}, {100.0: 5})
    res = _plan(ladder=False)
    assert res.cost == 45.0 and res.evaluations == 5 and res.history.tolist() == [45.0]
    assert res.message == ("plan of 100 m / 16; best of the lattices at 100 m: 100 m, any-angle links of 16 cells "
                           "(2 lattice paths screened, 1 refined to convergence)")


def test_an_end_point_that_is_not_free_is_its_status_before_any_lattice(rungs) -> None:  # type: ignore[no-untyped-def]
    r = rungs({}, {}, {})
    w = _world(0.0, 10000.0, 0.0, 10000.0)
    spec = PlannerSpec(name="grid", grid=GridParams(objective="length", cell=100.0))
    below = ladder.plan_ladder(PlanningProblem(w, np.array([1000.0, 5000.0, -400.0]), PATH[1], 1.5), spec)
    assert below.status is Status.INVALID_START and below.message.startswith("start [1000.0, 5000.0, -400.0] is not")
    goal = ladder.plan_ladder(PlanningProblem(w, PATH[0], np.array([20000.0, 5000.0, -100.0]), 1.5), spec)
    assert goal.status is Status.INVALID_GOAL and "outside the bounds" in goal.message
    assert r.calls == []
