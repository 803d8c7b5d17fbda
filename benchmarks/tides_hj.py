"""Peer: hj_reachability (JAX) on the 2D slice that ``benchmarks/tides.py`` writes (``slice.npz``).

hj_reachability and JAX go into their own venv (they must not change the project's numpy)::

    python3 -m venv /tmp/hjvenv && /tmp/hjvenv/bin/pip install hj_reachability
    /tmp/hjvenv/bin/python benchmarks/tides_hj.py results/tides        # after benchmarks/tides.py

The earliest arrival is the first time the goal enters the forward reachable set of the start:
``∂V/∂τ + max_u ∇V · (V_max u + c(x, τ)) = 0`` (forward in time, control maximising the front's
outward speed), ``V`` the signed distance to a disc of one cell about the start at the departure,
held positive on nodes that are not free (land, or seabed above the slice's depth), with the same
current table (bilinear in space, linear in time).  The disc biases the arrival early by about
one cell over the ground speed; the result gives that bias beside the time.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import hj_reachability as hj
import jax
import jax.numpy as jnp
import numpy as np


class Drift(hj.ControlAndDisturbanceAffineDynamics):
    """dx/dt = V u + c(x, t), |u| <= 1, with c from the table."""

    def __init__(self, cur, origin, step, t0, dt, speed):
        self.cur, self.origin, self.step, self.t0, self.dt = cur, origin, step, t0, dt
        super().__init__("max", "min", hj.sets.Ball(jnp.zeros(2), speed), hj.sets.Box(jnp.zeros(1), jnp.zeros(1)))

    def open_loop_dynamics(self, state, time):
        nt, nx, ny = self.cur.shape[:3]
        ft = jnp.clip((time - self.t0) / self.dt, 0.0, nt - 1.0)
        fx = jnp.clip((state[0] - self.origin[0]) / self.step[0], 0.0, nx - 1.0)
        fy = jnp.clip((state[1] - self.origin[1]) / self.step[1], 0.0, ny - 1.0)
        it, ix, iy = (jnp.minimum(jnp.floor(f).astype(int), n - 2) for f, n in ((ft, nt), (fx, nx), (fy, ny)))
        wt, wx, wy = ft - it, fx - ix, fy - iy
        c = 0.0
        for a, ca in ((0, 1 - wt), (1, wt)):
            for b, cb in ((0, 1 - wx), (1, wx)):
                for d, cd in ((0, 1 - wy), (1, wy)):
                    c = c + ca * cb * cd * self.cur[it + a, ix + b, iy + d]
        return c

    def control_jacobian(self, state, time):
        return jnp.eye(2)

    def disturbance_jacobian(self, state, time):
        return jnp.zeros((2, 1))


def main(folder: str, still: bool = False) -> None:
    d = dict(np.load(Path(folder) / "slice.npz"))
    if still:  # sanity check: no current, no land -> arrival (distance - disc) / speed
        d["cur"] = np.zeros_like(d["cur"])
        d["free"] = np.ones_like(d["free"])
    origin, step, shape = d["origin"][:2], d["step"][:2], tuple(int(v) for v in d["shape"][:2])
    lo, hi = origin, origin + step * (np.array(shape) - 1)
    grid = hj.Grid.from_lattice_parameters_and_boundary_conditions(hj.sets.Box(jnp.array(lo), jnp.array(hi)), shape)
    assert np.allclose(np.asarray(grid.states[0, 0]), lo) and np.allclose(np.asarray(grid.states[-1, -1]), hi)
    dyn = Drift(jnp.asarray(d["cur"]), jnp.asarray(origin), jnp.asarray(step), float(d["t0"]), float(d["dt"]),
                float(d["speed"]))
    start, goal, speed = d["start"][:2], d["goal"][:2], float(d["speed"])
    radius = float(step[0])
    v0 = jnp.linalg.norm(grid.states - jnp.asarray(start), axis=-1) - radius
    # blocked nodes held at +one cell (a huge value there would wreck the WENO stencils next to it)
    obstacle = jnp.where(jnp.asarray(d["free"]), -1e9, float(step[0]))
    settings = hj.SolverSettings.with_accuracy("high", value_postprocessor=hj.solver.static_obstacle(obstacle))
    times = float(d["t0"]) + np.arange(0.0, 16 * 3600.0 + 1.0, 300.0)
    gi = np.round((goal - lo) / step).astype(int)
    hj.solve(settings, dyn, grid, jnp.asarray(times[:3]), v0, progress_bar=False).block_until_ready()  # compile
    c0, w0 = time.process_time(), time.perf_counter()
    values = np.asarray(hj.solve(settings, dyn, grid, jnp.asarray(times), v0, progress_bar=False))
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    at_goal = values[:, gi[0], gi[1]]
    k = int(np.argmax(at_goal <= 0.0)) if (at_goal <= 0.0).any() else -1
    arrival = np.nan
    if k > 0:  # linear between the two snapshots around the crossing
        a0, a1 = at_goal[k - 1], at_goal[k]
        arrival = times[k - 1] + (times[k] - times[k - 1]) * a0 / (a0 - a1) - float(d["t0"])
    doc = {"peer": f"hj_reachability (jax {jax.__version__}), WENO3 + TVD-RK3, CFL 0.75", "grid": list(shape),
           "cell_m": float(step[0]), "arrival_s": arrival, "start_disc_m": radius,
           "disc_bias_s_approx": radius / speed, "cpu_s": cpu, "wall_s": wall, "snapshots": len(times)}
    print(json.dumps(doc))
    if not still:
        (Path(folder) / "hj_reachability.json").write_text(json.dumps(doc, indent=1))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "results/tides", "--still" in sys.argv)
