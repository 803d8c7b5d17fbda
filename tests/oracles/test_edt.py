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
