"""Cut the real Slocum dives of dbdreader's source distribution into a small CSV (issue 58).

dbdreader (Lucas Merckelbach, GPL-3.0-or-later) ships real Slocum G2 binary files from the
North Sea (gliders ``amadeus`` and ``sebastian``, 23 July 2014, one segment each of about 1.2 h
of 0-40 m yos).  This tool reads them with dbdreader itself and writes, per glider, the
navigation columns auvplan's glider flight model is checked against (``tests/data/slocum_dives_2014_204.csv``):

    glider, t (s since the first record), depth_m, pitch_rad, ballast_cc, heading_rad,
    speed_m_s (the glider's own m_speed), lat, lon (m_gps_lat/m_gps_lon when fixed, else NaN),
    water_vx, water_vy (the glider's own depth-averaged current m_water_vx/vy when reported, else NaN)

Usage (dbdreader installed, the sdist unpacked)::

    pip download --no-binary :all: --no-deps dbdreader -d /tmp/dbd && tar xzf /tmp/dbd/dbdreader-*.tar.gz -C /tmp/dbd
    pip install dbdreader
    python tools/cut_slocum_dives.py /tmp/dbd/dbdreader-0.6.3/dbdreader/data tests/data/slocum_dives_2014_204.csv
"""

from __future__ import annotations

import csv
import math
import sys
from pathlib import Path

import dbdreader  # type: ignore[import-not-found]  # GPL-3: a tool dependency only, never imported by auvplan
import numpy as np

GLIDERS = ("amadeus-2014-204-05-000", "sebastian-2014-204-05-000")
COLUMNS = ("m_depth", "m_pitch", "m_ballast_pumped", "m_heading", "m_speed", "m_gps_lat", "m_gps_lon",
           "m_water_vx", "m_water_vy")


def _on(t: np.ndarray, ts: np.ndarray, vs: np.ndarray) -> np.ndarray:
    """The values ``vs`` reported exactly at the times ``t`` (NaN elsewhere)."""
    out = np.full(t.shape, math.nan)
    idx = np.searchsorted(t, ts)
    ok = (idx < len(t)) & (np.abs(t[np.minimum(idx, len(t) - 1)] - ts) < 1e-6)
    out[idx[ok]] = vs[ok]
    return out


def main(data: str, out: str) -> None:
    rows = []
    for name in GLIDERS:
        dbd = dbdreader.DBD(str(Path(data) / f"{name}.dbd"), cacheDir=str(Path(data) / "cac"))
        t, depth = dbd.get("m_depth")
        cols = {"m_depth": depth}
        for c in COLUMNS[1:]:
            ts, vs = dbd.get(c)
            cols[c] = _on(t, ts, vs)
        for i in range(len(t)):
            rows.append([name.split("-")[0], f"{t[i] - t[0]:.3f}"] + [
                "" if math.isnan(cols[c][i]) else f"{cols[c][i]:.7g}" for c in COLUMNS])
        print(name, len(t), "records", file=sys.stderr)
    with open(out, "w", newline="") as fh:
        fh.write("# Derived from dbdreader 0.6.3's source distribution (dbdreader/data/amadeus-2014-204-05-000.dbd,\n"
                 "# sebastian-2014-204-05-000.dbd; Slocum G2 gliders, North Sea, 2014-07-23)\n"
                 "# by tools/cut_slocum_dives.py;\n"
                 "# GPL-3.0-or-later as distributed by dbdreader (Lucas Merckelbach). Values untouched.\n")
        w = csv.writer(fh)
        w.writerow(["glider", "t", "depth_m", "pitch_rad", "ballast_cc", "heading_rad", "speed_m_s", "lat", "lon",
                    "water_vx", "water_vy"])
        w.writerows(rows)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
