"""Cut GSHHG land polygons for a lon/lat box into a GeoJSON file (how the shipped cut-out was made).

Needs GMT and the GSHHG data: ``apt-get install gmt gmt-gshhg`` (GSHHG 2.3.7, LGPL).
``gmt coast -M -W`` dumps the level-1 shoreline pieces inside the box; shapely closes them
against the box (``polygonize``) and keeps the faces whose representative point
``gmt select -Ns/k`` places on land.

    python tools/gshhg_cutout.py -123.8 -122.55 48.0 48.55 --resolution h \\
        --out src/auvplan/data/gshhg_h_juan_de_fuca.geojson
"""

from __future__ import annotations

import argparse
import json
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import LineString, box, mapping
from shapely.ops import polygonize, unary_union


def shoreline_pieces(region: str, res: str) -> list[LineString]:
    text = subprocess.run(["gmt", "coast", f"-R{region}", f"-D{res}", "-M", "-W"], capture_output=True,
                          text=True, check=True).stdout
    pieces, cur = [], []
    for line in text.splitlines():
        if line.startswith(">"):
            if len(cur) > 1:
                pieces.append(LineString(cur))
            cur = []
        elif line.strip():
            cur.append(tuple(map(float, line.split()[:2])))
    if len(cur) > 1:
        pieces.append(LineString(cur))
    return pieces


def land_polygons(west: float, east: float, south: float, north: float, res: str):
    region = f"{west}/{east}/{south}/{north}"
    frame = box(west, south, east, north)
    faces = list(polygonize(unary_union(shoreline_pieces(region, res) + [frame.exterior])))
    pts = np.array([f.representative_point().coords[0] for f in faces])
    with tempfile.TemporaryDirectory() as tmp:
        f = Path(tmp) / "pts.txt"
        np.savetxt(f, pts, fmt="%.9f")
        out = subprocess.run(["gmt", "select", str(f), f"-R{region}", f"-D{res}", "-Ns/k"], capture_output=True,
                             text=True, check=True).stdout
    on_land = {tuple(np.round(list(map(float, ln.split()[:2])), 6)) for ln in out.splitlines()
               if ln.strip() and not ln.startswith(">")}
    land = [f for f, p in zip(faces, pts) if tuple(np.round(p, 6)) in on_land]
    return shapely.set_precision(unary_union(land), 1e-6)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    for name in ("west", "east", "south", "north"):
        p.add_argument(name, type=float)
    p.add_argument("--resolution", default="h", choices=list("fhilc"), help="GSHHG resolution (f = full)")
    p.add_argument("--out", required=True)
    a = p.parse_args()
    geom = land_polygons(a.west, a.east, a.south, a.north, a.resolution)
    fc = {"type": "FeatureCollection", "name": Path(a.out).stem,
          "features": [{"type": "Feature",
                        "properties": {"source": f"GSHHG 2.3.7 resolution {a.resolution}, level 1 shorelines (land)"},
                        "geometry": mapping(g)} for g in shapely.get_parts(geom)]}
    Path(a.out).write_text(json.dumps(fc, separators=(",", ":")))
    print(f"{len(fc['features'])} polygons, {shapely.get_num_coordinates(geom)} vertices → {a.out}")


if __name__ == "__main__":
    main()
