"""Write ``src/auvplan/data/tides_rotary.json``: a rotary (circular, clockwise) tidal current built
from the harmonic constants of one real NOAA current station of ``tides_salish.json``.

    .venv/bin/python tools/rotary_tide.py [--station PUG1702_5]

The station's constituents (amplitudes, phases, mean; XTide's yearly equilibrium arguments and
node factors, copied unchanged) drive the *east* component; the *north* component is the same
constituents a quarter of each one's period later (phase κ − 90°), so every constituent turns
clockwise on a circle, the current's direction turns with the tide and its speed changes with the
constituents' beat (spring/neap, diurnal inequality).  Both components are written as rectilinear
station records (flood 090° and 000°) at two sites 10⁻⁶° of latitude apart (0.11 m): the
inverse-distance mean of the two sites is then their average to 10⁻⁵ everywhere within 100 km, so
each record carries twice the station's amplitudes and mean.  The field is uniform in space: in open
water the least time is known exactly (docs/timeopt.md).  NOT FOR NAVIGATION, and not the current of
any real place: a test of planning in a current that turns and outruns the vehicle.
"""

from __future__ import annotations

import argparse
import copy
import json
from pathlib import Path

DATA = Path(__file__).resolve().parents[1] / "src" / "auvplan" / "data"


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--station", default="PUG1702_5")
    args = ap.parse_args()
    doc = json.loads((DATA / "tides_salish.json").read_text(encoding="utf-8"))
    st = next(s for s in doc["stations"] if s["station_id"] == args.station)
    east, north = copy.deepcopy(st), copy.deepcopy(st)
    for rec, axis, flood, dlat in ((east, "east", 90.0, 0.0), (north, "north", 0.0, 1e-6)):
        rec["name"] = f"{st['name']} harmonics, rotary: {axis} component"
        rec["station_id"] = f"{st['station_id']}-rotary-{axis}"
        rec["lat"] = st["lat"] + dlat
        rec["flood_dir_deg"], rec["ebb_dir_deg"] = flood, flood + 180.0
        rec["amplitude_m_s"] = {k: 2.0 * a for k, a in st["amplitude_m_s"].items()}
        rec["mean_m_s"] = 2.0 * st["mean_m_s"] if axis == "east" else 0.0
        rec.pop("direction_from", None)
    north["phase_deg"] = {k: (p - 90.0) % 360.0 for k, p in st["phase_deg"].items()}
    out = {k: v for k, v in doc.items() if k != "stations"}
    out["source"] = (f"built by tools/rotary_tide.py from station {st['station_id']} of tides_salish.json "
                     f"({doc['source']})")
    out["construction"] = __doc__.split("\n\n")[1].replace("\n", " ")
    out["stations"] = [east, north]
    (DATA / "tides_rotary.json").write_text(json.dumps(out, indent=1), encoding="utf-8")
    print("wrote", DATA / "tides_rotary.json")


if __name__ == "__main__":
    main()
