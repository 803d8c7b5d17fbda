"""The numpy/compiled morphology of ``auvplan.world.kernels.edt`` is scipy.ndimage's, bit for bit (issue 56:
the time-optimal planner and the zones' raster no longer import scipy.ndimage at a command's start).

Oracle: SciPy itself, on seeded random masks of many shapes (non-square, one row, one column, sparse and
dense), both row passes of the distance transform (numpy offsets and the compiled lower envelope)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from auvplan.world.kernels import edt


def _masks(seed: int, count: int, most: int = 24):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        ny, nx = (int(v) for v in rng.integers(1, most, 2))
        p = float(rng.choice([0.02, 0.2, 0.5, 0.8, 0.98]))
        yield rng.random((ny, nx)) < p


@pytest.mark.parametrize("small", [edt.SMALL, -1], ids=["numpy-offsets", "compiled-envelope"])
def test_distance_transform_is_scipys_to_the_bit(monkeypatch, small) -> None:
    monkeypatch.setattr(edt, "SMALL", small)
    masks = list(_masks(0, 300)) + [np.zeros((3, 5), bool), np.ones((4, 2), bool), np.eye(7, 3, dtype=bool) == 0]
    # far from any background: a single false element in a wide field, at a corner
    far = np.ones((9, 61), bool)
    far[8, 0] = False
    masks.append(far)
    for m in masks:
        ours, theirs = edt.distance_transform(m), ndimage.distance_transform_edt(m)
        assert ours.dtype == np.float64 and np.array_equal(ours.view(np.int64), theirs.view(np.int64)), m.shape


def test_dilation_and_window_or_are_scipys() -> None:
    rng = np.random.default_rng(1)
    for m in _masks(2, 200):
        it = int(rng.integers(1, 5))
        assert np.array_equal(edt.dilate_cross(m, it), ndimage.binary_dilation(m, iterations=it))
        m3 = np.repeat(m[:, :, None], int(rng.integers(1, 4)), axis=2) & (rng.random((*m.shape, 1)) < 0.7)
        size = tuple(int(2 * rng.integers(0, 4) + 1) for _ in range(3))
        got = edt.window_any(m3, size)
        assert got.dtype == bool and np.array_equal(got, ndimage.maximum_filter(m3, size=size, mode="nearest"))


def _counting(monkeypatch) -> dict[str, int]:
    """scipy.ndimage's three functions, each call counted (the answers SciPy's own)."""
    calls = {"distance_transform_edt": 0, "binary_dilation": 0, "maximum_filter": 0}
    for name in calls:
        real = getattr(ndimage, name)

        def counted(*args, _real=real, _name=name, **kwargs):
            calls[_name] += 1
            return _real(*args, **kwargs)

        monkeypatch.setattr(ndimage, name, counted)
    return calls


def test_the_covered_cases_never_call_scipy_and_the_others_are_scipys(monkeypatch) -> None:
    """Issue 56's contract: a 2D mask with a false element, a dilation of at least one step and an odd window are
    computed here, without SciPy (a command's start imports no scipy.ndimage); what is not covered (a mask with no
    false element, an empty or 3D mask, iterations 0 — SciPy's 'until nothing changes' —, an even window and its
    origin) is SciPy's own answer.  Oracle: SciPy (the call count, and its values from the originals)."""
    dt, dil, mf = ndimage.distance_transform_edt, ndimage.binary_dilation, ndimage.maximum_filter
    calls = _counting(monkeypatch)
    rng = np.random.default_rng(3)
    covered = [rng.random((5, 9)) < 0.6, np.array([[False]]), np.array([[True, False, True]]), np.eye(4, 1) == 0]
    for m in covered:
        assert np.array_equal(edt.distance_transform(m), dt(m))
        for it in (1, 2):
            assert np.array_equal(edt.dilate_cross(~m, it), dil(~m, iterations=it))
        for size in ((1, 1), (1, 3), (3, 5)):
            assert np.array_equal(edt.window_any(m, size), mf(m, size=size, mode="nearest"))
    assert calls == {"distance_transform_edt": 0, "binary_dilation": 0, "maximum_filter": 0}
    # handed to SciPy: each call counted, the value SciPy's
    m = rng.random((6, 7)) < 0.3
    m[0, 0] = True
    cases = [(edt.distance_transform, np.ones((3, 4), bool), lambda a: dt(a)),
             (edt.distance_transform, np.zeros((0, 3), bool), lambda a: dt(a)),
             (edt.distance_transform, rng.random((3, 4, 2)) < 0.5, lambda a: dt(a)),
             (lambda a: edt.dilate_cross(a, 0), m, lambda a: dil(a, iterations=0)),
             (lambda a: edt.window_any(a, (2, 3)), m, lambda a: mf(a, size=(2, 3), mode="nearest")),
             (lambda a: edt.window_any(a, (3, 4)), m, lambda a: mf(a, size=(3, 4), mode="nearest")),
             (lambda a: edt.window_any(a, (3,)), m, lambda a: mf(a, size=(3,), mode="nearest"))]
    for k, (ours, theirs, a) in enumerate((c[0], c[2], c[1]) for c in cases):
        before = sum(calls.values())
        if k == 6:  # a size for fewer axes than the mask has: SciPy refuses it, as ours does
            with pytest.raises(RuntimeError):
                ours(a)
        else:
            assert np.array_equal(ours(a), theirs(a)), k
        assert sum(calls.values()) == before + 1, k
