"""Slocum .ma files and the Seaglider targets file (issue 58), parsed by an independent reader of their syntax.

The reader here is written from the documented syntax, not from auvplan's: Slocum ``.ma`` (Teledyne Webb
Research, Slocum G2 Operators Manual; stock ``yo10.ma``/``surfac03.ma``, GGS ``goto_l10.ma``) —
``behavior_name=``, ``b_arg: NAME(UNIT) VALUE`` between ``<start:b_arg>``/``<end:b_arg>``, ``LON LAT`` in
DDMM.MMMM between ``<start:waypoints>``/``<end:waypoints>``, ``#`` comments; Seaglider ``targets``
(UW APL Seaglider File Formats Manual) — ``/`` comments, ``NAME lat=DDMM.MMMM lon=DDDMM.MMMM radius=R goto=NEXT``.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from auvplan.io.data.geo import LocalFrame
from auvplan.io.missions.glider import from_ddmm, seaglider_targets, slocum_files, to_ddmm
from auvplan.planners.timeopt.glider import cycle
from auvplan.vehicles.glider import GliderParams

B_ARG = re.compile(r"^\s*b_arg:\s+(\w+)\((\w+)\)\s+(-?\d+(?:\.\d+)?)\s*(?:#.*)?$")
TARGET = re.compile(r"^(\w+) lat=(-?\d+\.\d+) lon=(-?\d+\.\d+) radius=(\d+) goto=(\w+)$")


def _degrees(ddmm: str) -> float:
    """DDMM.MMMM (signed) as degrees, by string: the last two integer digits are minutes."""
    sign = -1.0 if ddmm.startswith("-") else 1.0
    whole, frac = ddmm.lstrip("-").split(".")
    return sign * (int(whole[:-2] or "0") + float(whole[-2:] + "." + frac) / 60.0)


def _ma(text: str) -> tuple[str, dict[str, tuple[str, float]], list[tuple[float, float]]]:
    lines = text.splitlines()
    assert lines[0].startswith("behavior_name=")
    name = lines[0].split("=", 1)[1]
    blk = lines[lines.index("<start:b_arg>") + 1: lines.index("<end:b_arg>")]
    args = {}
    for ln in blk:
        m = B_ARG.match(ln)
        assert m, ln
        args[m.group(1)] = (m.group(2), float(m.group(3)))
    wps = []
    if "<start:waypoints>" in lines:
        for ln in lines[lines.index("<start:waypoints>") + 1: lines.index("<end:waypoints>")]:
            body = ln.split("#", 1)[0].split()
            if body:
                assert len(body) == 2
                wps.append((_degrees(body[1]), _degrees(body[0])))  # (lat, lon): the file holds LON LAT
    return name, args, wps


# origins on both sides of the equator and of Greenwich (signs), and one beside the antimeridian
ORIGINS = [(67.25, 13.75), (-33.9, -151.2), (0.02, -0.01), (-54.0, 179.98)]


@pytest.mark.parametrize("origin", ORIGINS)
def test_slocum_files_parse_and_hold_the_waypoints(origin):
    rng = np.random.default_rng(58)
    pts = np.cumsum(rng.uniform(-3000.0, 3000.0, (7, 2)), axis=0)
    g = GliderParams(yos=4, dive_depth_m=350.0, climb_depth_m=15.0, surface_every_s=7200.0)
    c = cycle(g)  # 2 yos of 4030 s fit in 7200 s: the plan surfaces after 2 (test_edges17_slocum_surfacing.py)
    files = slocum_files(pts, origin, g, min_altitude=12.0, number=10, yos=c.yos, underwater_s=c.underwater_s)
    assert set(files) == {"goto_l10.ma", "yo10.ma", "surfac10.ma", "surfac11.ma"}
    name, args, wps = _ma(files["goto_l10.ma"])
    assert name == "goto_list" and args["num_waypoints"] == ("nodim", 7.0) and len(wps) == 7
    assert args["list_stop_when"][1] == 7 and args["list_when_wpt_dist"] == ("m", g.capture_radius_m)
    lon, lat = LocalFrame(*origin).inverse(pts[:, 0], pts[:, 1])
    got = np.array(wps)
    dlon = (got[:, 1] - lon + 180.0) % 360.0 - 180.0
    assert np.abs(got[:, 0] - lat).max() * 111e3 < 0.5  # 0.0001' is 0.19 m
    assert np.abs(dlon * np.cos(np.radians(lat))).max() * 111e3 < 0.5
    name, args, _ = _ma(files["yo10.ma"])
    assert name == "yo" and args["num_half_cycles_to_do"][1] == 2 * c.yos == 4
    assert args["d_target_depth"] == ("m", 350.0)
    assert args["c_target_depth"] == ("m", 15.0) and args["d_target_altitude"] == ("m", 12.0)
    assert args["d_pitch_value"][1] == pytest.approx(-math.radians(26.0), abs=1e-4) and args["end_action"][1] == 2
    name, args, _ = _ma(files["surfac10.ma"])
    assert name == "surface" and args["start_when"][1] == 2 and args["end_action"][1] == 2
    name, args, _ = _ma(files["surfac11.ma"])
    assert args["start_when"][1] == 12 and args["when_secs"] == ("sec", math.ceil(c.underwater_s * 3 / 2))


def test_no_time_surfacing_file_without_surface_every_s():
    files = slocum_files(np.zeros((2, 2)), (60.0, 5.0), GliderParams(), 10.0)
    assert "surfac11.ma" not in files


@pytest.mark.parametrize("origin", ORIGINS)
def test_seaglider_targets_parse_as_a_chain(origin):
    pts = np.array([[0.0, 0.0], [5000.0, -2000.0], [9000.0, 4000.0]])
    text = seaglider_targets(pts, origin, 1500.0)
    body = [ln for ln in text.splitlines() if not ln.startswith("/")]
    rows = [TARGET.match(ln) for ln in body]
    assert all(rows) and len(rows) == 3
    names = [r.group(1) for r in rows]
    gotos = [r.group(5) for r in rows]
    assert gotos[:-1] == names[1:] and gotos[-1] == names[-1]  # each to the next; the last holds
    assert {r.group(4) for r in rows} == {"1500"}
    lon, lat = LocalFrame(*origin).inverse(pts[:, 0], pts[:, 1])
    assert np.allclose([_degrees(r.group(2)) for r in rows], lat, atol=2e-6)
    assert np.allclose(((np.array([_degrees(r.group(3)) for r in rows]) - lon + 180) % 360) - 180, 0, atol=2e-6)


def test_ddmm_round_trip():
    rng = np.random.default_rng(7)
    for deg in np.r_[rng.uniform(-180.0, 180.0, 200), [-0.5, 0.0, 59.99999999, -179.999999]]:
        assert from_ddmm(to_ddmm(deg)) == pytest.approx(deg, abs=1e-7)  # (minutes that round to 60 carry)
        text = f"{to_ddmm(deg):.4f}"
        assert float(text.lstrip("-").split(".")[0][-2:]) < 60  # never 60 minutes in the file
        assert _degrees(text) == pytest.approx(deg, abs=2e-6)
    assert to_ddmm(-70.5) == -7030.0 and to_ddmm(41.25) == 4115.0 and f"{to_ddmm(59.99999999):.4f}" == "6000.0000"
