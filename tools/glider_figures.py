"""The glider's documented figures (issue 58): the flight model against real Slocum dives, the built-in mission.

Writes ``docs/figures/glider-dives.md`` (per held-out leg of dbdreader's amadeus and sebastian segments:
measured and modelled vertical speed, pitch and horizontal speed), ``docs/figures/glider-dac.md`` (the
depth-averaged current dead-reckoned with the model against the glider's own ``m_water_vx/vy``) and
``docs/figures/glider-lofoten.md`` (the built-in ``glider-lofoten`` planned, flown, and flown by the
nose-at-the-goal pilot).  Usage: ``.venv/bin/python tools/glider_figures.py`` then
``.venv/bin/python tools/docs_figures.py sync``.
"""

from __future__ import annotations

import csv
import math
import os
import time
from pathlib import Path

import numpy as np

from auvplan.vehicles.glider import G, GliderParams, attack_angle, pitch_for_speed, steady_glide
from auvplan.vehicles.glider_fit import calibrate, dead_reckoned_current, yo_legs

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data" / "slocum_dives_2014_204.csv"
FIG = ROOT / "docs" / "figures"


def _columns(glider: str) -> dict[str, np.ndarray]:
    with DATA.open() as fh:
        rows = list(csv.reader(line for line in fh if not line.startswith("#")))
    head, body = rows[0], [r for r in rows[1:] if r[0] == glider]
    return {h: np.array([float(r[i]) if r[i] else math.nan for r in body]) for i, h in enumerate(head) if i}


def dives() -> tuple[str, str]:
    """The per-leg table and the depth-averaged current table."""
    table = ["| glider | leg (t, s) | kind | w measured / model (m/s) | pitch measured / model (°) | "
             "u kinematic / model (m/s) | worst error |", "| --- | --- | --- | --- | --- | --- | --- |"]
    dac = ["| glider | underwater (s) | glider's own m_water_vx, vy (m/s) | model dead-reckoned (m/s) | "
           "difference (m/s) |", "| --- | --- | --- | --- | --- |"]
    for name in ("amadeus", "sebastian"):
        c = _columns(name)
        legs = yo_legs(c["t"], c["depth_m"], c["pitch_rad"], c["ballast_cc"])
        half = len(legs) // 2
        p = calibrate(GliderParams(), legs[:half])
        lift = p.hull_lift + p.wing_lift
        for lg in legs[half:]:
            pr = 1025.0 * G * lg.depth_m
            gl = steady_glide(p, lg.pitch, lg.ballast_cc, 1025.0, pr)
            th = float(pitch_for_speed(p, np.array(lg.w), lg.ballast_cc, 1025.0, pr))
            u_k = abs(lg.w) / math.tan(abs(lg.pitch + float(attack_angle(lg.pitch, p.cd0, p.cd1, lift))))
            errs = [float(gl.w) / lg.w - 1, th / lg.pitch - 1, float(gl.u) / u_k - 1]
            kind = "dive" if lg.w < 0 else "climb"
            table.append(f"| {name} | {lg.t:.0f} | {kind} | {lg.w:+.3f} / {float(gl.w):+.3f} "
                         f"| {math.degrees(lg.pitch):+.1f} / {math.degrees(th):+.1f} | {u_k:.3f} / {float(gl.u):.3f} "
                         f"| {100 * max(map(abs, errs)):.1f} % |")
        under = np.flatnonzero(c["depth_m"] > 1.0)
        fixed = np.isfinite(c["lat"])
        f0 = np.flatnonzero(fixed[: under[0]])[-1]
        f1 = under[-1] + np.flatnonzero(fixed[under[-1]:])[0]
        k = slice(f0, f1 + 1)
        vx, vy = dead_reckoned_current(p, c["t"][k], c["depth_m"][k], c["pitch_rad"][k], c["ballast_cc"][k],
                                       c["heading_rad"][k], (c["lat"][f0], c["lon"][f0]), (c["lat"][f1], c["lon"][f1]))
        own = under[-1] + np.flatnonzero(np.isfinite(c["water_vx"][under[-1]:]))[0]
        ox, oy = c["water_vx"][own], c["water_vy"][own]
        dac.append(f"| {name} | {c['t'][f1] - c['t'][f0]:.0f} | {ox:+.3f}, {oy:+.3f} | {vx:+.3f}, {vy:+.3f} | "
                   f"{math.hypot(vx - ox, vy - oy):.3f} |")
        table.append(f"| {name} | calibrated on the first {half} legs | | neutral density {p.neutral_density:.2f} "
                     f"kg/m³, C_D0 {p.cd0:.3f} | | | |")
    return "\n".join(table) + "\n", "\n".join(dac) + "\n"


def lofoten() -> str:
    """The built-in mission's line."""
    from auvplan.app.glider import glider_scenario

    clock = time.process_time()
    _, r = glider_scenario("glider-lofoten")
    cpu = time.process_time() - clock
    load = os.getloadavg()[0]
    return (f"planned {r['planned_duration_s'] / 3600:.2f} h, flown {r['flown_duration_s'] / 3600:.2f} h through the "
            f"current at every depth ({r['planned_vs_flown_pct']:.1f} % apart); the nose-at-the-goal pilot "
            f"{r['steady_heading_duration_s'] / 3600:.2f} h ({r['saved_vs_steady_heading_pct']:.1f} % saved); "
            f"{r['surfacings_planned']} dive cycles of {r['cycle_s'] / 3600:.2f} h at {r['cycle_speed_m_s']:.3f} m/s, "
            f"{r['flown_energy_j'] / 3600:.0f} Wh flown ({r['inflections']} pump strokes), endurance "
            f"{r['endurance_days']:.0f} days; plan and both flights {cpu:.1f} s CPU, load {load:.1f} on 2 cores "
            "(`tools/glider_figures.py`)")


class _Frozen:
    """The World's current frozen at one time (the plan of a planner without time)."""

    def __init__(self, base: object, t0: float) -> None:
        self.base, self.t0 = base, t0

    def velocity(self, points: np.ndarray, t: float = 0.0) -> np.ndarray:
        return self.base.velocity(points, self.t0)  # type: ignore[attr-defined]

    def sample(self, points: np.ndarray, times: np.ndarray) -> np.ndarray:
        v = self.velocity(np.asarray(points).reshape(-1, 3))
        return np.broadcast_to(v, (len(np.atleast_1d(times)), *v.shape)).copy()

    def covers(self, *box: float) -> bool:
        return self.base.covers(*box)  # type: ignore[attr-defined]

    @property
    def max_speed(self) -> float:
        return self.base.max_speed  # type: ignore[attr-defined]


def departures() -> str:
    """Planned vs flown, the plan for the current frozen at the departure, and the nose-at-the-goal pilot."""
    from dataclasses import replace

    from auvplan.io.scenario.loader import build, load
    from auvplan.planners.timeopt.glider import plan_glider
    from auvplan.sim.glider import fly_glider

    sc = load("glider-lofoten")
    world, m = build(sc)
    g, alt = m.vehicle.glider, sc.mission.min_altitude_m
    rows = ["| departure | planned (h) | flown (h) | apart | current frozen at departure, flown (h) | "
            "nose at the goal (h) | saved against it |", "| --- | --- | --- | --- | --- | --- | --- |"]
    for d in (0.0, 4 * 3600.0, 8 * 3600.0, 12 * 3600.0):
        pl = plan_glider(world, g, m.start, m.goal, d, alt, m.planner.timeopt)
        fl = fly_glider(world, g, m.start, pl.waypoints, d, min_altitude=alt, dac0=pl.currents[0])
        frozen = replace(world, currents=_Frozen(world.currents, d))
        ps = plan_glider(frozen, g, m.start, m.goal, d, alt, m.planner.timeopt)
        fs = fly_glider(world, g, m.start, ps.waypoints, d, min_altitude=alt, dac0=ps.currents[0])
        nv = fly_glider(world, g, m.start, [m.goal[:2]], d, min_altitude=alt, correct_current=False)
        p, f, s, n = ((x - d) / 3600 for x in (pl.arrive_s, fl.reach_s, fs.reach_s, nv.reach_s))
        rows.append(f"| +{d / 3600:.0f} h | {p:.2f} | {f:.2f} | {100 * abs(f - p) / p:.1f} % | {s:.2f} | {n:.2f} | "
                    f"{100 * (n - f) / n:.1f} % |")
    return "\n".join(rows) + "\n"


def picture(path: Path) -> None:
    """Plan view of glider-lofoten: depth-averaged current at the departure, the plan, both flights."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from auvplan.io.scenario.loader import build, load
    from auvplan.planners.timeopt.glider import DepthAveragedCurrent, cycle, plan_glider
    from auvplan.sim.glider import fly_glider

    sc = load("glider-lofoten")
    world, m = build(sc)
    g, alt = m.vehicle.glider, sc.mission.min_altitude_m
    pl = plan_glider(world, g, m.start, m.goal, 0.0, alt, m.planner.timeopt)
    fl = fly_glider(world, g, m.start, pl.waypoints, 0.0, min_altitude=alt, dac0=pl.currents[0])
    nv = fly_glider(world, g, m.start, [m.goal[:2]], 0.0, min_altitude=alt, correct_current=False)
    dac = DepthAveragedCurrent(world, g.climb_depth_m, g.dive_depth_m, alt,
                               surface_share=g.surface_time_s / cycle(g).duration_s)
    xs = np.linspace(-19000.0, 19000.0, 15)
    gx, gy = np.meshgrid(xs, xs)
    v = dac.velocity(np.stack([gx.ravel(), gy.ravel(), np.full(gx.size, -10.0)], axis=1), 0.0)
    fig, ax = plt.subplots(figsize=(6.4, 6.0))
    q = ax.quiver(gx / 1e3, gy / 1e3, v[:, 0], v[:, 1], np.hypot(v[:, 0], v[:, 1]), cmap="Blues", scale=3.0)
    fig.colorbar(q, ax=ax, label="depth-averaged current at departure (m/s)", shrink=0.8)
    ax.plot(fl.xyz[:, 0] / 1e3, fl.xyz[:, 1] / 1e3, "-", color="tab:green", lw=1.5, label="flown (plan)")
    ax.plot(nv.xyz[:, 0] / 1e3, nv.xyz[:, 1] / 1e3, "-", color="tab:red", lw=1.2, label="nose at the goal")
    ax.plot(pl.waypoints[:, 0] / 1e3, pl.waypoints[:, 1] / 1e3, "o", ms=4, color="k", label="planned fixes")
    ax.plot(*(np.array(m.start[:2]) / 1e3), "s", color="k")
    ax.add_patch(plt.Circle(np.array(m.goal[:2]) / 1e3, g.capture_radius_m / 1e3, fill=False, color="k"))
    ax.set_xlabel("x east (km)")
    ax.set_ylabel("y north (km)")
    ax.set_aspect("equal")
    ax.set_title("glider-lofoten: dive cycles across the coastal current")
    ax.legend(loc="lower left", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main() -> None:
    table, dac = dives()
    (FIG / "glider-dives.md").write_text(table)
    (FIG / "glider-dac.md").write_text(dac)
    (FIG / "glider-lofoten.md").write_text(lofoten() + "\n")
    (FIG / "glider-departures.md").write_text(departures())
    picture(ROOT / "docs" / "img" / "glider-lofoten.png")


if __name__ == "__main__":
    main()
