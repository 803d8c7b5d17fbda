import subprocess, json, sys
import numpy as np
import shapely
from shapely.geometry import LineString, box, mapping
from shapely.ops import polygonize, unary_union
res = sys.argv[1]
W, E, S, N = -123.8, -122.55, 48.0, 48.55
segs, cur = [], []
for line in open(f"lines_{res}.txt"):
    if line.startswith(">"):
        if len(cur) > 1: segs.append(LineString(cur))
        cur = []
    else:
        cur.append(tuple(map(float, line.split()[:2])))
if len(cur) > 1: segs.append(LineString(cur))
frame = box(W, S, E, N)
merged = unary_union(segs + [frame.exterior])
faces = list(polygonize(merged))
pts = np.array([f.representative_point().coords[0] for f in faces])
np.savetxt("pts.txt", pts, fmt="%.9f")
out = subprocess.run(["gmt", "select", "pts.txt", f"-R{W}/{E}/{S}/{N}", f"-D{res}", "-Ns/k"], capture_output=True, text=True).stdout
land_pts = {tuple(np.round(list(map(float, l.split()[:2])), 6)) for l in out.splitlines() if l.strip() and not l.startswith(">")}
land = [f for f, p in zip(faces, pts) if tuple(np.round(p, 6)) in land_pts]
print(len(faces), "faces", len(land), "land", "area deg2", sum(f.area for f in land), "vertices", sum(len(f.exterior.coords) + sum(len(i.coords) for i in f.interiors) for f in land))
geom = unary_union(land)
geom = shapely.set_precision(geom, 1e-6)
feat = {"type": "FeatureCollection", "name": f"gshhg_{res}_salish",
        "features": [{"type": "Feature", "properties": {"source": f"GSHHG 2.3.7 resolution {res}, level 1 shorelines (land)"},
                      "geometry": mapping(g)} for g in getattr(geom, "geoms", [geom])]}
json.dump(feat, open(f"gshhg_{res}_salish.geojson", "w"), separators=(",", ":"))
