"""Cut the NOAA tidal-current stations of the Strait of Juan de Fuca and the San Juan Islands out of
Debian's ``xtide-data`` into ``src/auvplan/data/tides_salish.json`` (no hand-typed constants).

    apt-get install xtide-data tcd-utils      # harmonics-dwf-*-free.tcd and restore_tide_db
    .venv/bin/python tools/cut_tides.py

``restore_tide_db`` (libtcd's own dumper) writes the TCD file as an XTide harmonics text file; this
script reads that text: the constituent speeds, XTide's tables of equilibrium arguments (Greenwich,
1 January 00:00 UTC of each year) and node factors (middle of each year), and the reference current
stations inside the box with their amplitudes (knots), phases (degrees, local epoch referred to the
station's time meridian), mean current (datum offset), flood (max) and ebb (min) directions and depth.
Stations whose record has no direction take it from the nearest depth of the same site.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
import tempfile
from pathlib import Path

TCD_GLOB = "/usr/share/xtide/harmonics-dwf-*-free.tcd"
BOX = (48.0, 48.5, -124.8, -122.75)  # lat min, lat max, lon min, lon max: the Strait of Juan de Fuca
YEARS = (2020, 2040)
OUT = Path(__file__).resolve().parents[1] / "src" / "auvplan" / "data" / "tides_salish.json"
KNOT = 1852.0 / 3600.0
FOOT = 0.3048


def _dump(tcd: Path) -> list[str]:
    with tempfile.TemporaryDirectory() as tmp:
        base = Path(tmp) / "dump"
        subprocess.run(["restore_tide_db", str(tcd), str(base)], check=True, capture_output=True)
        return (base.with_suffix(".txt")).read_text(encoding="latin-1").split("\n")


def _tables(lines: list[str]) -> tuple[list[str], list[float], int, dict, dict, int]:
    data = [ln for ln in lines if ln and not ln.startswith("#")]
    n = int(data[0])
    names = [d.split()[0] for d in data[1:n + 1]]
    speeds = [float(d.split()[1]) for d in data[1:n + 1]]
    start = int(data[n + 1])
    years = int(data[n + 2])
    i = n + 3

    def table(i):
        out = {}
        for name in names:
            vals = data[i].split()[1:]
            i += 1
            while len(vals) < years:
                vals += data[i].split()
                i += 1
            out[name] = [float(v) for v in vals]
        assert data[i].strip() == "*END*", data[i]
        return out, i + 1

    args, i = table(i)
    assert int(data[i]) == years
    nodes, i = table(i + 1)
    return names, speeds, start, args, nodes, years


def _stations(lines: list[str], names: list[str]) -> list[dict]:
    out = []
    k = 0
    while k < len(lines):
        if not lines[k].startswith("# BEGIN HOT COMMENTS"):
            k += 1
            continue
        hot = {}
        k += 1
        while lines[k].startswith("#"):
            key, _, val = lines[k][2:].partition(":")
            hot[key.strip()] = val.strip()
            k += 1
        name, zone, datum = lines[k], lines[k + 1], lines[k + 2]
        consts = lines[k + 3:k + 3 + len(names)]
        k += 3 + len(names)
        lat, lon = float(hot["!latitude"]), float(hot["!longitude"])
        depth = re.search(r"\(Depth ([0-9.]+)ft\)", name)
        if not (BOX[0] <= lat <= BOX[1] and BOX[2] <= lon <= BOX[3]) or "Current" not in name or depth is None:
            continue
        value, units = datum.split()
        assert units == "knots", (name, units)
        hh, mm = zone.split()[0].split(":")
        amp, phase = {}, {}
        for cname, row in zip(names, consts):
            parts = row.split()
            if parts[0] == "x":
                continue
            assert parts[0] == cname, (parts[0], cname)
            amp[cname] = round(float(parts[1]) * KNOT, 6)
            phase[cname] = float(parts[2])
        out.append({
            "name": name, "station_id": hot["station_id"], "lat": lat, "lon": lon,
            "depth_m": round(float(depth.group(1)) * FOOT, 2),
            "flood_dir_deg": float(hot["max_direction"]) if "max_direction" in hot else None,
            "ebb_dir_deg": float(hot["min_direction"]) if "min_direction" in hot else None,
            "mean_m_s": round(float(value) * KNOT, 6),
            "zone_hours": int(hh) + (1 if not hh.startswith("-") else -1) * int(mm) / 60.0,
            "source": hot.get("source", ""), "restriction": hot.get("restriction", ""),
            "amplitude_m_s": amp, "phase_deg": phase,
        })
    return out


def _fill_directions(stations: list[dict]) -> list[dict]:
    """Directions of a depth bin without one come from the nearest depth of the same site; sites
    with no direction at any depth are dropped."""
    kept = []
    for s in stations:
        if s["flood_dir_deg"] is None:
            same = [o for o in stations if o["lat"] == s["lat"] and o["lon"] == s["lon"]
                    and o["flood_dir_deg"] is not None]
            if not same:
                continue
            near = min(same, key=lambda o: abs(o["depth_m"] - s["depth_m"]))
            s = {**s, "flood_dir_deg": near["flood_dir_deg"], "ebb_dir_deg": near["ebb_dir_deg"],
                 "direction_from": near["station_id"]}
        kept.append(s)
    return kept


def main() -> int:
    tcd = sorted(Path("/").glob(TCD_GLOB.lstrip("/")))
    if not tcd:
        print(f"no {TCD_GLOB}: apt-get install xtide-data tcd-utils", file=sys.stderr)
        return 2
    lines = _dump(tcd[-1])
    names, speeds, start, args, nodes, _ = _tables(lines)
    stations = _fill_directions(_stations(lines, names))
    used = sorted({c for s in stations for c in s["amplitude_m_s"]}, key=names.index)
    y0, y1 = YEARS
    sl = slice(y0 - start, y1 - start + 1)
    doc = {
        "source": f"{tcd[-1].name} (Debian package xtide-data, David Flater's harmonics-dwf; NOAA/NOS "
                  "current stations, public domain), dumped with libtcd's restore_tide_db",
        "disclaimer": "NOT FOR NAVIGATION. Do not rely on this data for decisions that can result in harm "
                      "to anyone or anything (the data file's own notice).",
        "units": "m/s (converted from knots, 1 kn = 1852/3600 m/s); depths m (from feet); directions "
                 "degrees true (flood = max_direction, ebb = min_direction); phases degrees, local epoch "
                 "referred to the zone meridian zone_hours (XTide convention)",
        "first_year": y0,
        "constituents": used,
        "speed_deg_per_hour": [speeds[names.index(c)] for c in used],
        "equilibrium_deg": [args[c][sl] for c in used],
        "node_factor": [nodes[c][sl] for c in used],
        "stations": stations,
    }
    body = json.dumps({k: v for k, v in doc.items() if k != "stations"}, indent=1)[:-2]
    rows = ",\n  ".join(json.dumps(s, separators=(",", ":")) for s in stations)
    OUT.write_text(f'{body},\n "stations": [\n  {rows}\n ]\n}}\n')
    print(f"{len(stations)} station depths, {len(used)} constituents, years {y0}-{y1} -> {OUT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
