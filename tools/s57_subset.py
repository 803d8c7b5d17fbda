"""Cut a small S-57 test cell out of a NOAA ENC: a few features of the chosen object classes and only the
spatial records they use, written back as ISO 8211 records unchanged (``tests/data/US4MD81M_zones.000``).

An S-57 file is a data descriptive record followed by data records, each a 24-byte leader, a directory
of (tag, length, position) entries and a field area (ISO/IEC 8211).  Feature records (field ``FRID``:
``RCNM RCID PRIM GRUP OBJL ...``) point at spatial records by ``FSPT`` names (``RCNM`` byte + ``RCID``
uint32); edges point at their end nodes by ``VRPT``.  The cut keeps every record that is neither a
feature nor a spatial record (the data set's ``DSID``/``DSPM``: scale factors and datum), the chosen
features, and the spatial records they reach; byte for byte.

    python tools/s57_subset.py US4MD81M.000 tests/data/US4MD81M_zones.000
"""

from __future__ import annotations

import argparse
import struct
from pathlib import Path

#: Object class codes (IHO S-57 Appendix A) and how many features of each to keep.
KEEP = {94: 3, 159: 4, 112: 2, 86: 2, 20: 1}  # PIPSOL, WRECKS, RESARE, OBSTRN, CBLARE


def records(data: bytes) -> list[bytes]:
    """Split an ISO 8211 file into its records (each starts with its 5-digit length)."""
    out, i = [], 0
    while i < len(data):
        n = int(data[i:i + 5])
        out.append(data[i:i + n])
        i += n
    return out


def fields(rec: bytes) -> dict[str, bytes]:
    """The fields of a data record by tag (the last of a repeated tag)."""
    base = int(rec[12:17])
    sl, sp, st = int(rec[20:21]), int(rec[21:22]), int(rec[23:24])
    size = st + sl + sp
    out = {}
    directory = rec[24:base - 1]
    for k in range(0, len(directory), size):
        e = directory[k:k + size]
        tag, length, pos = e[:st].decode(), int(e[st:st + sl]), int(e[st + sl:size])
        out[tag] = rec[base + pos:base + pos + length]
    return out


def names(field: bytes, stride: int) -> set[tuple[int, int]]:
    """The (RCNM, RCID) names at the start of each repeated group of ``stride`` bytes."""
    body = field[:-1]  # the field terminator
    return {(body[k], struct.unpack("<I", body[k + 1:k + 5])[0]) for k in range(0, len(body) - stride + 1, stride)}


def subset(data: bytes) -> bytes:
    """The cut (see the module notes)."""
    recs = records(data)
    parsed = [fields(r) for r in recs[1:]]
    taken = {code: 0 for code in KEEP}
    features, used = set(), set()
    for i, f in enumerate(parsed):
        if "FRID" in f:
            objl = struct.unpack("<H", f["FRID"][7:9])[0]
            if objl in taken and taken[objl] < KEEP[objl] and "FSPT" in f:
                taken[objl] += 1
                features.add(i)
                used |= names(f["FSPT"], 8)
    nodes = set()
    for f in parsed:
        if "VRID" in f and (f["VRID"][0], struct.unpack("<I", f["VRID"][1:5])[0]) in used and "VRPT" in f:
            nodes |= names(f["VRPT"], 9)
    used |= nodes
    out = [recs[0]]
    for i, (r, f) in enumerate(zip(recs[1:], parsed, strict=True)):
        if "FRID" in f:
            keep = i in features
        elif "VRID" in f:
            keep = (f["VRID"][0], struct.unpack("<I", f["VRID"][1:5])[0]) in used
        else:
            keep = True
        if keep:
            out.append(r)
    return b"".join(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("source", type=Path)
    ap.add_argument("target", type=Path)
    args = ap.parse_args()
    if args.target.exists():
        raise SystemExit(f"{args.target}: exists (not overwritten)")
    args.target.write_bytes(subset(args.source.read_bytes()))
    print(f"wrote {args.target} ({args.target.stat().st_size} bytes)")


if __name__ == "__main__":
    main()
