"""``mission check`` of a user's own ``.plan`` whose geofence does not fit ArduPilot's fence storage fails it.

Only the export was held to the storage (test_edges17_fence_storage): a ``.plan`` drawn in QGroundControl with an
inclusion polygon of 84 vertices passed the check, and ArduSub refuses its upload ("Fence exceeds storage size",
``AC_PolyFence_loader::write_fence``).  The check now counts the ``.plan``'s ``geoFence`` as ArduPilot stores it,
with the export's own function (``deploy_formats.fence_storage_problem``) and names the bytes and the limit.

The oracle counts the bytes by hand from ``AC_PolyFence_loader``'s layout: a 4-byte header; per polygon 1 type byte,
1 count byte and 4 + 4 bytes of latitude and longitude per vertex; per circle 1 type byte, 8 of its centre and 4 of
its radius; and the end-of-storage byte, within 672 bytes (a 16 KiB board's ``StorageFence``).  The ``.plan`` files
are written here as QGroundControl writes them (``geoFence``: ``polygons`` of ``[lat, lon]`` vertices with
``inclusion``, ``circles`` of ``center`` and ``radius``)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import pytest

from auvplan import cli
from auvplan.io.data.geo import LocalFrame
from helpers import FLAT_SEA

ORIGIN = (16.0, 145.0)
FRAME = LocalFrame(*ORIGIN)
LIMIT = 672


def _latlon(x: float, y: float) -> list[float]:
    lon, lat = FRAME.inverse(x, y)
    return [round(float(lat), 9), round(float(lon), 9)]


def _ngon(n: int, cx: float, cy: float, r: float) -> list[list[float]]:
    return [_latlon(cx + r * math.cos(2 * math.pi * k / n), cy + r * math.sin(2 * math.pi * k / n)) for k in range(n)]


def _write(folder: Path, inclusion: int, exclusions: list[int], circles: int) -> Path:
    """A .plan (home at (1 km, 6 km), two waypoints 100 m deep along y = 6 km) with an inclusion polygon of
    ``inclusion`` vertices round the mission, exclusion polygons of ``exclusions`` vertices and exclusion circles,
    all away from the mission."""
    def item(x: float, y: float) -> dict[str, Any]:
        lat, lon = _latlon(x, y)
        return {"type": "SimpleItem", "autoContinue": True, "command": 16, "doJumpId": 0, "frame": 3,
                "params": [0, 0, 0, None, lat, lon, -100.0]}

    polygons = [{"inclusion": True, "polygon": _ngon(inclusion, 3000.0, 6000.0, 3500.0), "version": 1}]
    polygons += [{"inclusion": False, "polygon": _ngon(n, 1500.0 + 1500.0 * k, 8500.0, 300.0), "version": 1}
                 for k, n in enumerate(exclusions)]
    rings = [{"circle": {"center": _latlon(1500.0 + 1500.0 * k, 3500.0), "radius": 200.0}, "inclusion": False,
              "version": 1} for k in range(circles)]
    doc = {"fileType": "Plan", "version": 1, "groundStation": "QGroundControl",
           "geoFence": {"circles": rings, "polygons": polygons, "version": 2},
           "rallyPoints": {"points": [], "version": 2},
           "mission": {"version": 2, "firmwareType": 3, "vehicleType": 12, "cruiseSpeed": 1.5, "hoverSpeed": 1.5,
                       "plannedHomePosition": [*_latlon(1000.0, 6000.0), 0],
                       "items": [item(3000.0, 6000.0), item(5000.0, 6000.0)]}}
    path = folder / f"fence-{inclusion}-{'-'.join(map(str, exclusions))}-{circles}.plan"
    path.write_text(json.dumps(doc, indent=1))
    return path


# (inclusion vertices, exclusion polygons' vertices, exclusion circles, bytes counted by hand)
CASES = [
    (83, [], 0, 4 + (2 + 8 * 83) + 1),  # 671: the largest single polygon
    (84, [], 0, 4 + (2 + 8 * 84) + 1),  # 679: one vertex more
    (75, [3, 3], 1, 4 + (2 + 8 * 75) + 2 * (2 + 8 * 3) + (1 + 12) + 1),  # 672: exactly the limit
    (80, [3], 0, 4 + (2 + 8 * 80) + (2 + 8 * 3) + 1),  # 673: one byte over
]


@pytest.mark.parametrize(("inclusion", "exclusions", "circles", "want"), CASES,
                         ids=["83-vertices-671", "84-vertices-679", "at-the-limit-672", "one-byte-over-673"])
def test_a_plan_fence_over_the_storage_fails_the_check(tmp_path, capsys, inclusion, exclusions, circles, want):
    assert want in (671, 679, 672, 673)
    toml = tmp_path / "flat.toml"
    toml.write_text('name = "flat-300"\n' + FLAT_SEA)
    path = _write(tmp_path, inclusion, exclusions, circles)
    code = cli.main(["mission", "check", str(path), "--scenario", str(toml), "--json"])
    rec = json.loads(capsys.readouterr().out)
    rec = rec[0] if isinstance(rec, list) else rec
    fits = want <= LIMIT
    assert rec["deploy"]["envelope"]["ok"]  # the mission is inside the fence: only the storage can fail it
    assert rec["ok"] is fits and code == (0 if fits else 1)
    store = rec["deploy"]["fence_storage"]
    assert store["bytes"] == want and store["limit_bytes"] == LIMIT and store["ok"] is fits
    code = cli.main(["mission", "check", str(path), "--scenario", str(toml)])
    out = capsys.readouterr().out
    assert code == (0 if fits else 1)
    failing = [ln for ln in out.splitlines() if "geofence FAIL" in ln]
    if fits:
        assert not failing
    else:
        assert len(failing) == 1 and f"takes {want} bytes" in failing[0] and f"the {LIMIT} bytes" in failing[0]
