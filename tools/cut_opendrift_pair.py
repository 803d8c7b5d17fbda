"""Cut two ocean models over the same sea and dates out of OpenDrift's source distribution (issue 39).

OpenDrift (GPL-2.0, https://github.com/OpenDrift/opendrift) bundles, for its 2 February 2016 test case off
Lofoten, output of two different MET Norway ROMS models: the Nordic-4km hindcast (daily means on s-levels,
2016-02-02 to 02-04) and the Arctic-20km forecast (daily fields interpolated to z-levels, 2016-02-01 to 02-05,
on a polar-stereographic grid).  Usage::

    pip download --no-deps --no-binary :all: opendrift==1.14.12 -d /tmp/od
    tar xzf /tmp/od/opendrift-1.14.12.tar.gz -C /tmp/od
    python tools/cut_opendrift_pair.py /tmp/od/opendrift-1.14.12/tests/test_data src/auvplan/data

Writes ``nordic4km_lofoten_cut.nc`` and ``arctic20km_lofoten_cut.nc``.  Values are copied, never edited; only
index ranges (and, for Arctic-20km, the upper 300 m of its depth levels) are cut.
"""

from __future__ import annotations

import sys
from pathlib import Path

import xarray as xr

__all__ = ["cut_nordic_lofoten", "cut_arctic_lofoten"]

NORDIC = "2Feb2016_Nordic_sigma_3d/Nordic_subset.nc"
ARCTIC = "2Feb2016_Nordic_sigma_3d/Arctic20_1to5Feb_2016.nc"
NOTE = ("Cut by auvplan tools/cut_opendrift_pair.py from OpenDrift 1.14.12's tests/test_data/{} (OpenDrift: "
        "GPL-2.0); model output of MET Norway (Norwegian Meteorological Institute), {}")


def cut_nordic_lofoten(src: Path, out: Path) -> None:
    """Nordic-4km: every node and day of OpenDrift's subset, the variables auvplan reads."""
    ds = xr.open_dataset(src / NORDIC, decode_times=False)
    keep = ["u", "v", "zeta", "h", "angle", "mask_rho", "mask_u", "mask_v", "Cs_r", "hc", "Vtransform",
            "Vstretching", "theta_s", "theta_b", "lat_rho", "lon_rho"]
    cut = ds[keep]
    for name in ("u", "v"):
        cut[name].attrs.pop("coordinates", None)
        cut[name].encoding.pop("coordinates", None)
    cut.attrs = {k: ds.attrs[k] for k in ("title", "type", "Conventions")}
    cut.attrs["source"] = NOTE.format(NORDIC, "Nordic-4km hindcast daily averages of 2016-02-02 to 2016-02-04")
    enc = {v: {"zlib": True, "complevel": 9} for v in ("u", "v", "zeta", "h")}
    cut.to_netcdf(out / "nordic4km_lofoten_cut.nc", encoding=enc)


def cut_arctic_lofoten(src: Path, out: Path) -> None:
    """Arctic-20km: the nodes round the Nordic-4km subset, its five days, the depth levels down to 300 m."""
    ds = xr.open_dataset(src / ARCTIC, decode_times=False)
    keep = ["u", "v", "h", "mask", "polar_stereographic", "latitude", "longitude"]
    cut = ds[keep].isel(Y=slice(0, 10), X=slice(10, 24), depth=slice(0, 12))
    cut.attrs = {k: ds.attrs[k] for k in ("title", "Conventions", "grid_resolution", "grid_projection",
                                          "bulletin_type", "forecast_reference_time")}
    cut.attrs["source"] = NOTE.format(ARCTIC, "Arctic-20km forecast of 2016-02-01 to 2016-02-05 (z-levels)")
    enc = {v: {"zlib": True, "complevel": 9} for v in ("u", "v", "h")}
    cut.to_netcdf(out / "arctic20km_lofoten_cut.nc", encoding=enc)


if __name__ == "__main__":
    source, target = Path(sys.argv[1]), Path(sys.argv[2])
    cut_nordic_lofoten(source, target)
    cut_arctic_lofoten(source, target)
