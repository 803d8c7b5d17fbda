"""Current fields at the planner's scale: one population's midpoints (50 paths x 199 segments).

Times ``velocity`` of the Lamb-Oseen field of marcus-wake and of gridded fields the size of a
regional ocean-model extract (41 x 41 nodes; 1 level steady, or 20 levels x 25 times), beside
``scipy.interpolate.RegularGridInterpolator`` on the same grid, points and time in the same run,
and checks that both give the same velocities.

    .venv/bin/python benchmarks/currents.py --repeats 50
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy.interpolate import RegularGridInterpolator

from auvplan.io.scenario import loader as sc
from auvplan.world import GriddedCurrent


def per_call(fn, repeats: int) -> float:
    """Median seconds of ``fn()`` over ``repeats`` calls (after one warm-up call)."""
    fn()
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def scipy_peer(g: GriddedCurrent, t: np.ndarray):
    """RegularGridInterpolator on the same data, points clamped to the grid as auvplan does."""
    axes = [a if a.size > 1 else np.r_[a, a + 1.0] for a in (t, np.asarray(g.z), np.asarray(g.y), np.asarray(g.x))]
    data = np.stack([np.asarray(g.u), np.asarray(g.v), np.zeros_like(np.asarray(g.u))], axis=-1)
    data = data.reshape(t.size, g.z.size, g.y.size, g.x.size, 3)
    data = np.tile(data, [2 if a.size == 1 else 1 for a in (t, g.z, g.y, g.x)] + [1])
    interp = RegularGridInterpolator(axes, data)
    lo, hi = [a[0] for a in axes], [a[-1] for a in axes]

    def velocity(points, when):
        q = np.c_[np.full(len(points), when), points[:, 2], points[:, 1], points[:, 0]]
        return interp(np.clip(q, lo, hi))

    return velocity


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=50)
    args = ap.parse_args(argv)
    rng = np.random.default_rng(0)
    points = rng.uniform([0.0, 0.0, -6000.0], [1e5, 1e5, 0.0], (50 * 199, 3))
    world, _ = sc.build(sc.load("marcus-wake"))
    us = per_call(lambda: world.currents.velocity(points), args.repeats)
    print(f"Lamb-Oseen, 3 vortices, {len(points)} points: {us * 1e3:.3f} ms")
    x = np.linspace(0.0, 1e5, 41)
    for label, nz, nt in (("steady, 1 level", 1, 1), ("20 levels x 25 times", 20, 25)):
        z = np.linspace(-6000.0, 0.0, nz) if nz > 1 else np.zeros(1)
        t = np.linspace(0.0, 86400.0, nt)
        u, v = (rng.normal(0.0, 0.3, (nt, nz, 41, 41)) for _ in range(2))
        g = GriddedCurrent(x, x, z, u, v, None, t if nt > 1 else None)
        peer = scipy_peer(g, t)
        when = 0.3 * t[-1]
        assert np.allclose(g.velocity(points, when), peer(points, when), rtol=1e-12, atol=1e-12)
        ours = per_call(lambda g=g, when=when: g.velocity(points, when), args.repeats)
        theirs = per_call(lambda peer=peer, when=when: peer(points, when), args.repeats)
        print(f"gridded {label}, {len(points)} points: auvplan {ours * 1e3:.3f} ms, "
              f"scipy RegularGridInterpolator {theirs * 1e3:.3f} ms ({theirs / ours:.1f}x)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
