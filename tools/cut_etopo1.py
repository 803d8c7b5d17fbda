"""Cut the small ETOPO1 0.1° tiles that auvplan ships out of the grid bundled in the pybacktrack wheel.

    pip download --no-deps pybacktrack==1.5.0 -d /tmp/pbt && cd /tmp/pbt && unzip -q pybacktrack-*.whl
    .venv/bin/python tools/cut_etopo1.py /tmp/pbt/pybacktrack/bundle_data/topography/ETOPO1_0.1.grd [NAME ...]

Writes ``src/auvplan/data/etopo1_<name>.nc`` for each region below, or for the regions named (values
point-sampled, as in the source grid; see ``src/auvplan/data/PROVENANCE.md``).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import xarray as xr

REGIONS = {  # name: (lat_min, lat_max, lon_min, lon_max), degrees; lon in [-180, 180]
    "ninetyeast": (-12.0, -9.2, 87.6, 90.8),
    "new_england": (37.4, 39.5, -63.3, -60.4),
    "chagos": (-7.4, -4.6, 70.4, 73.3),
    "mariana": (15.8, 19.0, 144.2, 147.4),
}


def cut(grid: xr.Dataset, box: tuple[float, float, float, float], name: str) -> xr.Dataset:
    lat0, lat1, lon0, lon1 = box
    lon = np.round(np.linspace(lon0, lon1, int(round((lon1 - lon0) / 0.1)) + 1), 1)
    lat = np.round(np.linspace(lat0, lat1, int(round((lat1 - lat0) / 0.1)) + 1), 1)
    z = grid.z.sel(lat=lat, lon=np.mod(lon, 360.0), method="nearest").values.astype(np.float32)
    ds = xr.Dataset(
        {"elevation": (("lat", "lon"), z, {"units": "m", "standard_name": "height_above_mean_sea_level",
                                           "positive": "up"})},
        coords={"lat": ("lat", lat, {"units": "degrees_north", "standard_name": "latitude"}),
                "lon": ("lon", lon, {"units": "degrees_east", "standard_name": "longitude"})},
        attrs={"title": f"etopo1_{name}: cut-out of ETOPO1 Bedrock at 0.1 degree",
               "source": "ETOPO1 1 arc-minute global relief model (NOAA NGDC; Amante and Eakins 2009, "
                         "doi:10.7289/V5C8276M), 0.1 degree grid as bundled in pybacktrack 1.5.0 "
                         "(bundle_data/topography/ETOPO1_0.1.grd)",
               "license": "public domain (NOAA)"},
    )
    return ds


def main(src: str, names: list[str]) -> None:
    grid = xr.open_dataset(src)
    out = Path(__file__).resolve().parents[1] / "src" / "auvplan" / "data"
    for name, box in REGIONS.items():
        if names and name not in names:
            continue
        ds = cut(grid, box, name)
        path = out / f"etopo1_{name}.nc"
        ds.to_netcdf(path, encoding={"elevation": {"zlib": True}})
        z = ds.elevation.values
        print(f"{path.name}: {z.shape[0]} x {z.shape[1]}, {box}, seabed {z.min():.0f} .. {z.max():.0f} m, "
              f"{path.stat().st_size} bytes")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2:])
