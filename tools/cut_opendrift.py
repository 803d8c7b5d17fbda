"""Cut the two MET Norway ROMS samples shipped in ``auvplan/data`` out of OpenDrift's source distribution.

OpenDrift (GPL-2.0, https://github.com/OpenDrift/opendrift) bundles real output of MET Norway's
operational ROMS models in its ``tests/test_data``.  Usage::

    pip download --no-deps --no-binary :all: opendrift==1.14.12 -d /tmp/od
    tar xzf /tmp/od/opendrift-1.14.12.tar.gz -C /tmp/od
    python tools/cut_opendrift.py /tmp/od/opendrift-1.14.12/tests/test_data src/auvplan/data

Writes ``norkyst800_stere_cut.nc`` (NorKyst-800m surface currents on its polar-stereographic grid,
velocity along the grid's axes) and ``nordic4km_slevels_cut.nc`` (Nordic-4km currents on ROMS
s-levels, staggered Arakawa-C u/v, with ``angle``, ``h``, ``zeta``, ``Cs_r``, ``hc``, ``Vtransform``).
Values are copied, never edited; only index ranges are cut.
"""

from __future__ import annotations

import sys
from pathlib import Path

import xarray as xr

NORKYST = "16Nov2015_NorKyst_z_surface/norkyst800_subset_16Nov2015.nc"
NORDIC = "2Feb2016_Nordic_sigma_3d/Nordic-4km_SLEVELS_avg_00_subset2Feb2016.nc"
NOTE = ("Cut by auvplan tools/cut_opendrift.py from OpenDrift 1.14.12's tests/test_data/{} (OpenDrift: GPL-2.0); "
        "model output of MET Norway (Norwegian Meteorological Institute), {}")


def cut_norkyst(src: Path, out: Path) -> None:
    ds = xr.open_dataset(src / NORKYST, decode_times=False)
    cut = ds[["u", "v", "projection_stere"]].isel(time=slice(0, 4), Y=slice(110, 150), X=slice(150, 190))
    cut.attrs = {k: ds.attrs[k] for k in ("title", "type", "Conventions")}
    cut.attrs["source"] = NOTE.format(NORKYST, "NorKyst-800m forecast of 2015-11-16, surface level")
    enc = {v: {"zlib": True, "complevel": 9} for v in ("u", "v")}
    cut.to_netcdf(out / "norkyst800_stere_cut.nc", encoding=enc)


def cut_nordic(src: Path, out: Path) -> None:
    ds = xr.open_dataset(src / NORDIC, decode_times=False)
    keep = ["u", "v", "zeta", "h", "angle", "mask_rho", "mask_u", "mask_v", "Cs_r", "hc", "Vtransform",
            "Vstretching", "theta_s", "theta_b", "lat_rho", "lon_rho"]
    box = {"eta_rho": slice(40, 58), "xi_rho": slice(20, 38), "eta_u": slice(40, 58), "xi_u": slice(20, 38),
           "eta_v": slice(40, 58), "xi_v": slice(20, 38)}
    cut = ds[keep].isel(ocean_time=slice(0, 1), **box)
    cut = cut.drop_vars([c for c in ("lat_u", "lon_u", "lat_v", "lon_v") if c in cut.variables])
    for name in ("u", "v"):
        cut[name].attrs.pop("coordinates", None)
        cut[name].encoding.pop("coordinates", None)
    cut.attrs = {k: ds.attrs[k] for k in ("title", "type", "Conventions")}
    cut.attrs["source"] = NOTE.format(NORDIC, "Nordic-4km hindcast daily average of 2016-02-02")
    enc = {v: {"zlib": True, "complevel": 9} for v in ("u", "v", "zeta")}
    cut.to_netcdf(out / "nordic4km_slevels_cut.nc", encoding=enc)


if __name__ == "__main__":
    source, target = Path(sys.argv[1]), Path(sys.argv[2])
    cut_norkyst(source, target)
    cut_nordic(source, target)
