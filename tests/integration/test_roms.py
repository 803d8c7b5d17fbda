"""ROMS/CROCO currents on s-levels and staggered points (issue 30, point 4).

Oracles: files built from the transform equations with a field linear in depth (and in the XI
index, to catch a staggering offset), read back at known depths; the shipped Nordic-4km cut-out
(real MET Norway output) against a column-by-column computation written here.
"""

from __future__ import annotations

from importlib import resources

import numpy as np
import pytest
import xarray as xr

from auvplan.io.data.geo import LocalFrame
from auvplan.io.data.ocean.currents import CurrentsFileSpec, read_currents
from auvplan.io.data.ocean.roms import read_s_levels

NY, NX, NS = 8, 9, 12
LAT = 60.0 + 0.01 * np.arange(NY)
LON = 5.0 + 0.02 * np.arange(NX)
A, B, E = 0.2, 1e-3, 0.01  # u = A + B z + E xi   (xi: position in rho-index units along XI)
C, D, F = -0.1, -5e-4, 0.02  # v = C + D z + F eta


def _stretching(n):
    s = (np.arange(n) - n + 0.5) / n  # s_rho: -1 < s < 0
    return s, np.sinh(3.0 * s) / np.sinh(3.0)  # a simple stretching curve with C(-1) = -1, C(0) = 0


def _z(s, cs, h, hc, zeta, vt):
    """The transform equations, written out per level (the oracle side)."""
    out = []
    for sk, ck in zip(s, cs):
        if vt == 1:
            z0 = hc * sk + (h - hc) * ck
            out.append(z0 + zeta * (1.0 + z0 / h))
        else:
            z0 = (hc * sk + h * ck) / (hc + h)
            out.append(zeta + (zeta + h) * z0)
    return np.stack(out)


def _file(tmp_path, vt, h_rho, zeta):
    s, cs = _stretching(NS)
    hc = 20.0
    h_u = 0.5 * (h_rho[:, :-1] + h_rho[:, 1:])  # ROMS: h at u points, the mean of its two rho points
    h_v = 0.5 * (h_rho[:-1] + h_rho[1:])
    z_u = _z(s, cs, h_u, hc, zeta, vt)
    z_v = _z(s, cs, h_v, hc, zeta, vt)
    xi_u = np.arange(NX - 1) + 0.5  # u[k] between rho k and k + 1
    eta_v = np.arange(NY - 1) + 0.5
    u = A + B * z_u + E * xi_u[None, None, :]
    v = C + D * z_v + F * eta_v[None, :, None]
    lat, lon = np.meshgrid(LAT, LON, indexing="ij")
    ds = xr.Dataset(
        {"u": (("ocean_time", "s_rho", "eta_u", "xi_u"), u[None], {"units": "meter second-1"}),
         "v": (("ocean_time", "s_rho", "eta_v", "xi_v"), v[None], {"units": "meter second-1"}),
         "h": (("eta_rho", "xi_rho"), h_rho, {"units": "meter"}),
         "zeta": (("ocean_time", "eta_rho", "xi_rho"), np.full((1, NY, NX), zeta), {"units": "meter"}),
         "Cs_r": (("s_rho",), cs), "hc": ((), hc), "Vtransform": ((), vt),
         "angle": (("eta_rho", "xi_rho"), np.zeros((NY, NX)), {"units": "radians"}),
         "lat_rho": (("eta_rho", "xi_rho"), lat, {"units": "degree_north"}),
         "lon_rho": (("eta_rho", "xi_rho"), lon, {"units": "degree_east"})},
        coords={"s_rho": ("s_rho", s, {"standard_name": "ocean_s_coordinate_g2"}),
                "ocean_time": ("ocean_time", [0.0], {"units": "seconds since 2020-01-01"})})
    path = tmp_path / f"roms_vt{vt}.nc"
    ds.to_netcdf(path)
    return path, _z(s, cs, h_rho, hc, zeta, vt)


@pytest.mark.parametrize("vt, zeta, sloping", [(1, 0.0, True), (2, 0.7, False), (1, -0.4, False)])
def test_synthetic_s_levels_read_back_at_known_depths(tmp_path, vt, zeta, sloping):
    """u, v linear in z: every depth between a column's top and bottom rho level reads back exactly (up to the
    horizontal regridding of a field linear in the index); the XI/ETA terms catch a half-cell staggering slip."""
    jj, ii = np.meshgrid(np.arange(NY), np.arange(NX), indexing="ij")
    h = 150.0 + 25.0 * ii + 10.0 * jj if sloping else np.full((NY, NX), 220.0)
    path, z_rho = _file(tmp_path, vt, h, zeta)
    frame = LocalFrame(float(LAT.mean()), float(LON.mean()))
    g = read_currents(CurrentsFileSpec(str(path)), frame)
    checked = 0
    for j in range(2, NY - 2):
        for i in range(2, NX - 2):
            x, y = frame.forward(LON[i], LAT[j])
            top, bottom = z_rho[-1, j, i], z_rho[0, j, i]
            for zt in (-2.0, -10.0, -30.0, -75.0, -100.0, -150.0):  # the levels the reader interpolates to
                if not bottom < zt < top:
                    continue
                vel = g.velocity(np.array([[x, y, zt]]), 0.0)[0]
                assert vel[0] == pytest.approx(A + B * zt + E * i, abs=2e-4)
                assert vel[1] == pytest.approx(C + D * zt + F * j, abs=2e-4)
                checked += 1
    assert checked > 40
    assert g.z[0] < -100.0 and g.z[-1] == 0.0


def _data(name):
    return str(resources.files("auvplan") / "data" / name)


def test_nordic_s_levels_against_a_column_computation():
    """Real Nordic-4km output (Vtransform 2, 35 levels, staggered, rotated by `angle`): the reader's values on
    its depth levels equal a computation written here column by column (destagger, rotate, depths by the
    Vtransform 2 equation, linear interpolation)."""
    path = _data("nordic4km_slevels_cut.nc")
    with xr.open_dataset(path) as ds:
        grid, _, levels, comps = read_s_levels(ds, "u", "v", path, lambda d: None, lambda u, w: 1.0)
        assert int(ds["Vtransform"]) == 2 and float(ds["hc"]) == 30.0
        u, v = ds["u"].values[0].astype(float), ds["v"].values[0].astype(float)
        h, zeta, ang = ds["h"].values, ds["zeta"].values[0], ds["angle"].values
        s, cs, hc = ds["s_rho"].values, ds["Cs_r"].values, float(ds["hc"])
    rng = np.random.default_rng(4)
    for _ in range(25):
        j, i = rng.integers(1, h.shape[0] - 1), rng.integers(1, h.shape[1] - 1)
        uc = 0.5 * (u[:, j, i - 1] + u[:, j, i])
        vc = 0.5 * (v[:, j - 1, i] + v[:, j, i])
        e = uc * np.cos(ang[j, i]) - vc * np.sin(ang[j, i])
        n = uc * np.sin(ang[j, i]) + vc * np.cos(ang[j, i])
        z = zeta[j, i] + (zeta[j, i] + h[j, i]) * (hc * s + h[j, i] * cs) / (hc + h[j, i])
        for k, zt in enumerate(levels):
            got_e, got_n = comps["u"][0, k, j - 1, i - 1], comps["v"][0, k, j - 1, i - 1]
            if zt < -h[j, i]:
                assert np.isnan(got_e)
                continue
            assert got_e == pytest.approx(np.interp(zt, z, e), abs=1e-9)
            assert got_n == pytest.approx(np.interp(zt, z, n), abs=1e-9)
    assert grid.kind == "curvilinear" and levels.max() == 0.0 and levels.min() <= -1000.0
