"""``validate`` decided without a compiled kernel where a bound settles it (issue 56), against the compiled path.

A survey's seabed check and its size check take the seabed in numpy with its bound
(:meth:`Terrain.elevation_bounds`) and fall back to the compiled seabed only when the bound does not settle
the verdict; each is run here both ways (the compiled path forced by making the bound inconclusive) on
rough non-square grids far from the origin, over random areas turned by random angles, with a shoal that
crosses the surface (exact zeros included), for both sensors and both mountings, at budgets bracketing the
compiled estimate (an ulp under it, at it): the verdict and the message must be the same, and the numpy path must
decide most cases alone.  The zones' fine field made at its first use equals the one made at construction
and is shared with the sets derived from it.
"""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from auvplan.errors import ScenarioError
from auvplan.io.files import limits as _limits
from auvplan.io.results import survey as sv
from auvplan.survey.lines.placement import LineParams
from auvplan.survey.lines.swath import Sensor
from auvplan.survey.mission import SurveyParams
from auvplan.world import Bounds, Margins, Terrain, World


def _world(shoal: bool, seed: int, min_depth: float = 0.0) -> World:
    rng = np.random.default_rng(seed)
    x = 612_000.0 + np.arange(41) * 412.5  # non-square cells far from zero
    y = -4_300_000.0 + np.arange(27) * 250.0
    z = -180.0 + 60.0 * rng.standard_normal((y.size, x.size))
    if shoal:  # a bank reaching above the surface, with nodes exactly at zero
        gx, gy = np.meshgrid(np.arange(x.size), np.arange(y.size))
        z = z + 260.0 * np.exp(-((gx - 20.0) ** 2 + (gy - 13.0) ** 2) / 30.0)
        z[13, 18:23] = 0.0
    t = Terrain(x, y, z, name="rough")
    return World(Bounds(x[0], x[-1], y[0], y[-1], -1000.0, 0.0), t, margins=Margins(min_depth=min_depth))


def _area(world: World, rng: np.random.Generator) -> shapely.Polygon:
    """A random convex area turned by a random angle, inside the grid."""
    x0, x1, y0, y1 = world.terrain.extent
    c = np.array([rng.uniform(x0 + 4000, x1 - 4000), rng.uniform(y0 + 2500, y1 - 2500)])
    ang = rng.uniform(0, 2 * np.pi, 9)
    r = rng.uniform(600.0, 2200.0, 9)
    pts = np.column_stack([np.cos(ang) * r, np.sin(ang) * r])
    turn = rng.uniform(0, 2 * np.pi)
    rot = np.array([[np.cos(turn), -np.sin(turn)], [np.sin(turn), np.cos(turn)]])
    return shapely.convex_hull(shapely.MultiPoint(c + pts @ rot.T))


SENSORS = [Sensor("multibeam", 120.0, 0.0, "surface"), Sensor("multibeam", 90.0, 0.0, "auv", 30.0),
           Sensor("sidescan", 90.0, 150.0, "auv", 20.0), Sensor("sidescan", 90.0, 400.0, "surface")]


def _outcome(call) -> str:
    try:
        call()
    except ScenarioError as exc:
        return str(exc)
    return "ok"


def _forced(monkeypatch: pytest.MonkeyPatch, call) -> str:
    """``call``'s outcome with every bound inconclusive: the compiled seabed decides."""
    with monkeypatch.context() as m:
        m.setattr(sv, "_swath_bounds", lambda *a: None)
        m.setattr(sv, "_seabed_bounds", lambda w, x, y: (np.full(np.shape(x), np.inf),) * 2)
        return _outcome(call)


def _compiled_calls(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    calls = [0]
    real = Terrain.elevation

    def counted(self, x, y):
        calls[0] += 1
        return real(self, x, y)

    monkeypatch.setattr(Terrain, "elevation", counted)
    return calls


def _estimate(monkeypatch: pytest.MonkeyPatch, params: SurveyParams, world: World) -> float:
    """The compiled size check's estimate (bytes)."""
    seen: list[float] = []
    real = _limits.check
    with monkeypatch.context() as m:
        m.setattr(_limits, "check", lambda limits, where, what, nbytes, **kw: seen.append(nbytes))
        _forced(m, lambda: sv.check_survey_size(params, world, "s.toml: [survey]"))
    assert _limits.check is real and len(seen) == 1
    return seen[0]


@pytest.mark.parametrize("sensor", SENSORS, ids=lambda s: f"{s.kind}-{s.mounting}")
def test_the_size_check_decides_as_the_compiled_one(monkeypatch, sensor):
    calls = _compiled_calls(monkeypatch)
    rng = np.random.default_rng(hash((sensor.kind, sensor.mounting)) % 2**32)
    decided = total = 0
    for shoal in (False, True):
        world = _world(shoal, 7)
        for _ in range(3):
            params = SurveyParams(_area(world, rng), sensor, LineParams(overlap_max=0.3, station_m=25.0, step_m=5.0))
            nbytes = _estimate(monkeypatch, params, world)
            # budgets (MiB: a power of two, so exact) an ulp under the compiled estimate, at it, and about it
            for over, mb in ((True, 1e-3 * nbytes / 2**20), (True, np.nextafter(nbytes, 0.0) / 2**20),
                             (False, nbytes / 2**20), (False, (1 + 1e-9) * nbytes / 2**20), (False, 1e3 * nbytes)):
                with _limits.budget(_limits.Limits(memory_mb=mb)):
                    def call(params: SurveyParams = params, world: World = world) -> None:
                        sv.check_survey_size(params, world, "s.toml: [survey]")
                    before = calls[0]
                    fast = _outcome(call)
                    decided += calls[0] == before
                    total += 1
                    assert fast == _forced(monkeypatch, call), (shoal, mb)
                    assert (fast == "ok") is not over, (shoal, mb, fast)
    assert decided >= total // 3  # the numpy bound settles the clear passes without the compiled seabed


@pytest.mark.parametrize("min_depth", [0.0, 12.0])
def test_the_seabed_check_decides_as_the_compiled_one(monkeypatch, min_depth):
    calls = _compiled_calls(monkeypatch)
    rng = np.random.default_rng(5 + int(min_depth))
    outcomes = set()
    decided = total = 0
    for shoal in (False, True):
        world = _world(shoal, 11, min_depth)
        for _ in range(12):
            area = _area(world, rng)
            before = calls[0]
            def call(area: shapely.Polygon = area, world: World = world) -> None:
                sv._check_seabed(area, world, "s.toml: [survey]")
            fast = _outcome(call)
            decided += calls[0] == before
            total += 1
            assert fast == _forced(monkeypatch, call)
            outcomes.add(fast == "ok")
    assert outcomes == {True, False}  # dry and wet areas both met
    assert decided >= total // 3


def test_the_bounds_hold_the_compiled_swath_on_many_samples():
    """The bound pair of :func:`_swath_bounds` holds :func:`_swath` of the compiled depths, and is None
    exactly when a sample's depth could fall on either side of zero."""
    world = _world(True, 3)
    t = world.terrain
    rng = np.random.default_rng(9)
    x = rng.uniform(t.x[0], t.x[-1], 3000)
    y = rng.uniform(t.y[0], t.y[-1], 3000)
    x[:40] = t.x[20]  # on the shoal's zero nodes: the compiled value is exactly 0
    y[:40] = t.y[13]
    seen = {True: 0, False: 0}
    for sensor in SENSORS:
        params = SurveyParams(shapely.box(0, 0, 1, 1), sensor, LineParams(overlap_max=0.25))
        for k in range(0, 3000, 100):
            sx, sy = x[k:k + 100], y[k:k + 100]
            got = sv._swath_bounds(params, world, sx, sy)
            depth = -t.elevation(sx, sy)
            seen[got is None] += 1
            if got is None:
                continue
            spacing, swath = sv._swath(params, depth[np.isfinite(depth) & (depth > 0)])
            assert got[0] <= spacing and got[1] >= swath
            assert got[0] >= spacing * (1 - 1e-9) and got[1] <= swath * (1 + 1e-9)  # and a tight one
    assert seen[True] and seen[False]


def test_the_zones_fine_field_is_made_at_its_first_use_and_shared():
    from auvplan.world.zones import Zone, Zones
    from auvplan.world.zones.parts import distance_field

    rng = np.random.default_rng(4)
    zones = tuple(Zone(f"z{i}", shapely.buffer(shapely.Point(rng.uniform(0, 9000), rng.uniform(0, 5000)),
                                                rng.uniform(50, 400)), top=0.0, bottom=np.inf)
                  for i in range(25))
    padded = Zones(zones, pad=40.0)
    assert "_fine" not in padded.__dict__  # nothing made by construction
    exact = padded.exact  # derived before the field was made: takes its parent's when used
    eager = distance_field(padded._grid, padded._rings, padded._bounds)
    assert exact._field is padded._field
    for a, b in zip(padded._field, eager):
        assert np.array_equal(np.asarray(a), np.asarray(b))


def test_the_seabed_under_altitude_positions_is_the_compiled_one_from_the_cache(monkeypatch, tmp_path):
    """marcus-terrain-follow's positions given as altitudes, placed on two rough grids: the z of every placed
    position is the compiled seabed plus the altitude to the bit, computed (first build) and read back from the
    readers' cache (second); the other grid under the same points is a new entry, not the first grid's."""
    from auvplan.io.scenario import build as b
    from auvplan.io.scenario import loader

    monkeypatch.setenv("AUVPLAN_CACHE", "1")
    monkeypatch.setenv("AUVPLAN_CACHE_DIR", str(tmp_path))
    s = loader.load("marcus-terrain-follow")
    refs = s.geo.altitudes
    xs, ys = [r.x for r in refs], [r.y for r in refs]
    rng = np.random.default_rng(12)
    x = np.linspace(min(xs) - 3000.0, max(xs) + 3000.0, 53)
    y = np.linspace(min(ys) - 2000.0, max(ys) + 2000.0, 31)
    z = -3000.0 + 400.0 * rng.standard_normal((y.size, x.size))
    for grid in (Terrain(x, y, z, name="a"), Terrain(x, y, z + 0.3 * rng.standard_normal(z.shape), name="b")):
        for _ in range(2):  # computed, then read back
            placed = b._place_altitudes(s, grid)
            start = placed.mission.start
            want = float(grid.elevation(refs[0].x, refs[0].y)) + refs[0].altitude
            assert refs[0].path[-1] == "start" and start[2] == want
            route = np.asarray(placed.mission.route)
            assert np.array_equal(route[:, 2], grid.elevation(route[:, 0], route[:, 1]) + 50.0)
    assert len(list(tmp_path.glob("seabed-at-*.npz"))) == 2


def test_the_blas_question_asked_of_the_files(monkeypatch, tmp_path):
    """:func:`auvplan.runtime.jit._blas_installed` answers as importing SciPy's BLAS does: yes in this
    environment, no for a SciPy whose folder holds no ``linalg/cython_blas`` extension."""
    import importlib.util
    import sys
    import types

    from auvplan.runtime.jit import _blas_installed

    assert _blas_installed() is (importlib.util.find_spec("scipy.linalg.cython_blas") is not None)
    (tmp_path / "linalg").mkdir()
    (tmp_path / "linalg" / "cython_blas.pxd").write_text("")  # the declarations, not the extension
    monkeypatch.setitem(sys.modules, "scipy", types.SimpleNamespace(__path__=[str(tmp_path)]))
    assert _blas_installed() is False
