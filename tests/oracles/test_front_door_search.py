"""What ``data inspect`` no longer imports scipy.optimize and scipy.ndimage for (issue 56), against the
libraries themselves and a brute-force search.

* :func:`~auvplan.optim.bounded_min.bounded_min` is SciPy's bounded Brent step for step: the same
  points, the same bits (``x``, ``fun``, ``nfev``) as ``minimize_scalar(method="bounded")``;
* :func:`~auvplan.io.data.regrid.inscribed_extent`'s sides against a dense two-stage search of each
  projected edge, on non-square windows far north and south, turned in the frame (an origin away from
  the data), on both sides of the antimeridian, and on a rotated-pole grid;
* :func:`~auvplan.world.seabed.window_max` is ``scipy.ndimage.maximum_filter(mode="nearest")`` bit for bit;
* the conservative model, which no longer interpolates the nodes it then replaces, equals the one made
  through :func:`~auvplan.io.data.regrid.to_local` and :func:`~auvplan.io.data.seabed_model.node_indices`.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from pyproj import CRS, Transformer
from scipy import ndimage
from scipy.optimize import minimize_scalar

from auvplan.io.data import regrid
from auvplan.io.data.geo import LocalFrame
from auvplan.io.data.grids import HorizontalGrid
from auvplan.io.data.seabed_model import _projection_margin, model_seabed, node_indices
from auvplan.optim.bounded_min import bounded_min
from auvplan.world.seabed import conservative_nodes, window_max

FUNCTIONS = {
    "parabola inside": (lambda x: (x - 0.3) ** 2, 0.0, 1.0, 1e-12),
    "minimum at the low end": (lambda x: x**3 + 2.0 * x, 0.0, 2.0, 1e-12),
    "minimum at the high end": (lambda x: -math.exp(x), -1.0, 0.5, 1e-9),
    "flat": (lambda x: 4.0, -3.0, 3.0, 1e-12),
    "quartic, coarse tolerance": (lambda x: (x - 2.0) * x * (x + 2.0) ** 2, -3.0, -1.0, 1e-5),
    "wiggly": (lambda x: math.sin(7.0 * x) + 0.1 * x, -2.0, 2.5, 1e-12),
    "tiny interval": (lambda x: math.cos(x), 3.1, 3.1 + 1e-9, 1e-12),
    "empty interval": (lambda x: x * x, 0.25, 0.25, 1e-12),
}


@pytest.mark.parametrize("name", list(FUNCTIONS))
def test_bounded_min_is_scipys_bounded_brent(name):
    f, lo, hi, xatol = FUNCTIONS[name]
    seen_ours: list[float] = []
    seen_scipy: list[float] = []
    x, fun, nfev = bounded_min(lambda q: seen_ours.append(q) or f(q), lo, hi, xatol=xatol)
    res = minimize_scalar(lambda q: seen_scipy.append(float(q)) or f(q), bounds=(lo, hi), method="bounded",
                          options={"xatol": xatol})
    assert seen_ours == seen_scipy  # the same points, in the same order, bit for bit
    assert (x, fun, nfev) == (float(res.x), float(res.fun), res.nfev)


SHAPES = {
    "eighths": lambda x: round(8.0 * x) / 8.0, "thirds": lambda x: math.floor(3.0 * x),
    "double well": lambda x: (x * x - 1.0) ** 2, "square root": lambda x: abs(x) ** 0.5,
    "parabola": lambda x: (x - 0.3) ** 2, "wiggly": lambda x: math.sin(7.0 * x) + 0.1 * x,
    "quantised V": lambda x: round(512.0 * abs(x - 0.1)) / 512.0,
}
# (shape, offset, lo, hi, xatol, maxfun): intervals a few tolerances wide, far from zero on either side, step
# functions whose equal values tie the comparisons, and the parabolic step's acceptance tests (seeded search)
EDGES = [
    ("eighths", 1e6, 999999.9931462468, 1000000.0005185803, 3.395646773377549e-12, 20),
    ("thirds", -1e6, -1000000.0024967787, -999999.9886617817, 2.014159680966892e-08, 500),
    ("double well", 0.0, -3.9660896885767014e-10, 1.7195760427261648e-10, 1.327144827927598e-10, 500),
    ("double well", -34.0643430080014, -34.06434300800365, -34.06434300799819, 2.2001034839940736e-06, 500),
    ("thirds", 0.5495851898175845, 0.5139007189971465, 0.5616670019224091, 1.0450074038944738e-11, 500),
    ("square root", 224.17821377482892, 224.17820339110992, 224.1782165283611, 5.882587025626004e-07, 500),
    ("square root", 0.0909315831274542, 0.09092310280795494, 0.09096047278696905, 3.3583229066495267e-12, 20),
    ("parabola", 0.0, -0.6122109426477688, 0.5100120214083482, 0.00012141845567677517, 20),
    ("double well", 0.0, -5.068912532049851, 4.8596821391208165, 2.1612428711078274e-07, 7),
    ("wiggly", 0.0, -3.1440592209902016, 1.4890060647857766, 3.07410305439782e-08, 500),
    ("quantised V", -0.878724386962543, -0.9253453069826731, 2.0823431482737638, 1.8075672167099404e-07, 500),
    ("quantised V", 0.0, -1.996689306803087, 5.638168402946205, 2.092159983970347e-10, 500),
]


@pytest.mark.parametrize("case", EDGES, ids=[f"{c[0]}-{k}" for k, c in enumerate(EDGES)])
def test_bounded_min_is_scipys_at_its_tolerances_ties_and_far_from_zero(case):
    """Oracle: SciPy, as above, where the tolerance, the ties of equal values and the parabola's acceptance decide
    the steps."""
    shape, c, lo, hi, xatol, maxfun = case
    seen_ours: list[float] = []
    seen_scipy: list[float] = []
    x, fun, nfev = bounded_min(lambda q: seen_ours.append(q) or SHAPES[shape](q - c), lo, hi, xatol=xatol,
                               maxfun=maxfun)
    res = minimize_scalar(lambda q: seen_scipy.append(float(q)) or SHAPES[shape](float(q) - c), bounds=(lo, hi),
                          method="bounded", options={"xatol": xatol, "maxiter": maxfun})
    assert seen_ours == seen_scipy
    assert (x, fun, nfev) == (float(res.x), float(res.fun), res.nfev)


def test_bounded_min_stops_at_maxfun_and_refuses_bad_bounds():
    x, _, nfev = bounded_min(lambda q: math.sin(50.0 * q), 0.0, 10.0, xatol=1e-14, maxfun=7)
    res = minimize_scalar(lambda q: math.sin(50.0 * q), bounds=(0.0, 10.0), method="bounded",
                          options={"xatol": 1e-14, "maxiter": 7})
    assert (x, nfev) == (float(res.x), res.nfev) == (x, 7)
    with pytest.raises(ValueError, match="lower bound"):
        bounded_min(abs, 1.0, 0.0)
    with pytest.raises(ValueError, match="finite"):
        bounded_min(abs, 0.0, math.inf)


def _edge_extreme(to_local, edge, comp: int, sign: float) -> float:
    """``sign``-extreme (max for +1) of the local component ``comp`` along an edge ``s -> (row, col)``: dense
    samples, then dense samples again about the best one (spacing 2.5e-8 of the edge)."""
    s = np.linspace(0.0, 1.0, 4_001)
    v = sign * to_local(*edge(s))[comp]
    k = int(np.argmax(v))
    s2 = np.linspace(s[max(k - 1, 0)], s[min(k + 1, s.size - 1)], 20_001)
    return float(max(v[k], np.max(sign * to_local(*edge(s2))[comp])))


def _lonlat(frame: LocalFrame):
    return lambda r, c: frame.forward(c, r)


def _rotated(crs: CRS, frame: LocalFrame):
    tr = Transformer.from_crs(crs, "EPSG:4326", always_xy=True)

    def to_local(r, c):
        lon, lat = tr.transform(np.asarray(c, dtype=float), np.asarray(r, dtype=float))
        return frame.forward(lon, lat)
    return to_local


ROTATED_POLE = CRS.from_proj4("+proj=ob_tran +o_proj=longlat +o_lat_p=38 +o_lon_p=0 +lon_0=-170 +datum=WGS84 "
                              "+no_defs +type=crs")
GRIDS = {  # name: (kind, rows, cols, crs, frame origin lat, lon)
    "non-square far north": ("lonlat", (66.0, 67.1, 40), (20.0, 22.4, 31), None, 66.55, 21.2),
    "non-square far south, turned (origin away)": ("lonlat", (-58.0, -57.2, 25), (140.0, 141.9, 50), None,
                                                   -56.0, 137.5),
    "across the antimeridian, origin west of it": ("lonlat", (51.0, 52.0, 21), (179.3, 180.9, 45), None,
                                                   51.5, 179.9),
    "across the antimeridian, origin east of it": ("lonlat", (51.0, 52.0, 21), (179.3, 180.9, 45), None,
                                                   51.4, -179.6),
    "rotated pole": ("projected", (-1.2, 0.6, 30), (-0.7, 1.4, 22), ROTATED_POLE, 52.2, 10.6),
}


@pytest.mark.parametrize("name", list(GRIDS))
def test_inscribed_extent_against_a_dense_search(name, monkeypatch):
    kind, (r0, r1, nr), (c0, c1, nc), crs, lat0, lon0 = GRIDS[name]
    grid = HorizontalGrid(kind, np.linspace(r0, r1, nr), np.linspace(c0, c1, nc), crs)
    frame = LocalFrame(lat0, lon0)
    to_local = _lonlat(frame) if crs is None else _rotated(crs, frame)
    edges = {"west": (lambda s: (r0 + s * (r1 - r0), np.full_like(s, c0)), 0, 1.0),
             "east": (lambda s: (r0 + s * (r1 - r0), np.full_like(s, c1)), 0, -1.0),
             "south": (lambda s: (np.full_like(s, r0), c0 + s * (c1 - c0)), 1, 1.0),
             "north": (lambda s: (np.full_like(s, r1), c0 + s * (c1 - c0)), 1, -1.0)}
    dense = [sign * _edge_extreme(to_local, edge, comp, sign) + sign * 1e-3 for edge, comp, sign in edges.values()]
    kept = regrid.inscribed_extent(grid, frame)
    monkeypatch.setattr(regrid, "_inside_footprint", lambda g, f, rect: rect)  # the edge search alone
    sides = regrid.inscribed_extent(grid, frame)
    assert np.allclose(sides, dense, rtol=0.0, atol=1e-6), (sides, dense)
    # the result lies inside the footprint (the ring of the edges, densely)
    s = np.linspace(0.0, 1.0, 2001)
    ring = [to_local(*edges["south"][0](s)), to_local(*edges["east"][0](s)), to_local(*edges["north"][0](s[::-1])),
            to_local(*edges["west"][0](s[::-1]))]
    poly = shapely.Polygon(np.column_stack([np.concatenate([p[0] for p in ring]),
                                            np.concatenate([p[1] for p in ring])]))
    assert poly.is_valid and poly.contains(shapely.box(kept[0], kept[2], kept[1], kept[3]))
    area = (kept[1] - kept[0]) * (kept[3] - kept[2])
    assert kept == tuple(sides) or area < (sides[1] - sides[0]) * (sides[3] - sides[2])


@pytest.mark.parametrize("shape", [(1, 1), (1, 6), (9, 1), (23, 40), (120, 77)])
@pytest.mark.parametrize("reach", [0, 1, 2, 3, 6, 13, 70])
def test_window_max_is_ndimage_maximum_filter(shape, reach):
    a = np.random.default_rng(reach * 1000 + shape[0]).normal(size=shape)
    assert np.array_equal(window_max(a, reach), ndimage.maximum_filter(a, size=2 * reach + 1, mode="nearest"))


@pytest.mark.parametrize("factor", [0.5, 2.5])
def test_conservative_model_is_the_one_made_through_to_local(factor):
    """The nodes projected once and not interpolated: the same axes and node values, bit for bit, as the
    model made the long way (to_local's axes, node_indices, conservative_nodes), across the antimeridian."""
    grid = HorizontalGrid("lonlat", np.linspace(-12.0, -11.4, 31), np.linspace(179.7, 180.5, 45))
    la, lo = np.meshgrid(grid.rows, grid.cols, indexing="ij")
    z = -3000.0 + 800.0 * np.sin(la * 9.0) * np.cos(lo * 13.0)
    frame = LocalFrame(-11.7, -179.9)
    cell = 1852.0 * factor
    x, y, zn, fit = model_seabed(grid, z, frame, extent_m=None, cell_m=cell, method="conservative", what="t")
    ext = regrid.inscribed_extent(grid, frame)
    x0, y0 = regrid._target_axes(grid, frame, ext, cell, "t")
    x1, y1, _ = regrid.to_local(grid, z, frame, extent_m=(x0[0], x0[-1], y0[0], y0[-1]), cell_m=cell)
    fr, fc = node_indices(grid, frame, x1, y1)
    long_way = conservative_nodes(z, fr, fc, _projection_margin(grid, frame, z, x1, y1, fr, fc))
    assert np.array_equal(x, x1) and np.array_equal(y, y1) and np.array_equal(zn, long_way)
    assert fit is not None and fit.deficit_max_m <= 1e-6
