"""The zones' index: the prisms (grown by the pad, or :attr:`ZoneIndex.exact`), their R-tree, the broad
phase's cell grid, built once, and the fine lower-bound field, at its first use; the broad phase's candidate pairs."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Self

import numpy as np
import shapely

from ..._types import ArrayLike, BoolArray, FloatArray, IntArray
from ...errors import DataError
from ..terrain import Terrain
from .broad import candidates_kernel
from .parts import band_tops, distance_field, inner_centres, rasterise
from .parts import rings as polygon_rings
from .spec import Zone

__all__ = ["ZoneIndex"]


@dataclass(frozen=True, eq=False)
class ZoneIndex:
    """Many no-go prisms behind an R-tree (shapely ``STRtree``) of their footprints: the data and the broad
    phase of :class:`~auvplan.world.zones.Zones` (which adds the queries).

    Parameters
    ----------
    zones : tuple of Zone
        The prisms (may be empty).
    terrain : Terrain or None
        Seabed for the zones given ``above_seabed``; required when any is.
    pad : float, default 0.0
        Every prism grown by this much (m: footprints buffered, bands widened) in every query: the
        planners keep this far off, so a plan that skirts a zone stays outside it once densified,
        simplified into a mission and rounded in a file.  :attr:`exact` is the same zones unpadded
        (what checks of flown or exported missions test against).

    Raises
    ------
    DataError
        If a seabed zone comes without a terrain.
    """

    zones: tuple[Zone, ...]
    terrain: Terrain | None = None
    pad: float = 0.0
    _tree: shapely.STRtree = field(init=False, repr=False)
    _geoms: np.ndarray = field(init=False, repr=False)
    _zlo: FloatArray = field(init=False, repr=False)
    _zhi: FloatArray = field(init=False, repr=False)
    _h: FloatArray = field(init=False, repr=False)
    _seabed: BoolArray = field(init=False, repr=False)
    _bounds: FloatArray = field(init=False, repr=False)
    _grid: tuple[Any, ...] | None = field(init=False, repr=False)
    _rings: tuple[FloatArray, IntArray, IntArray, FloatArray] = field(init=False, repr=False)
    _centres: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        zs = tuple(self.zones)
        object.__setattr__(self, "zones", zs)
        h = np.array([np.nan if z.above_seabed is None else z.above_seabed for z in zs], dtype=float)
        if np.isfinite(h).any() and self.terrain is None:
            bad = next(z.name for z in zs if z.above_seabed is not None)
            raise DataError(f"zone {bad!r}: above_seabed_m needs a seabed (a [terrain])")
        if not (math.isfinite(self.pad) and self.pad >= 0):
            raise DataError(f"zones: pad must be a non-negative number, got {self.pad}")
        footprints = np.array([z.footprint for z in zs], dtype=object)
        object.__setattr__(self, "_centres", inner_centres(footprints))
        geoms = shapely.buffer(footprints, self.pad, join_style="mitre") if self.pad > 0 and zs else footprints
        self._set_prisms(geoms, h)
        self._rasterise()

    def _set_prisms(self, geoms: np.ndarray, h: FloatArray) -> None:
        """The footprints (grown by the pad), their R-tree, rings and discs, and the bands grown by the pad."""
        zs = self.zones
        geoms = np.array(geoms, dtype=object)
        shapely.prepare(geoms)
        object.__setattr__(self, "_geoms", geoms)
        object.__setattr__(self, "_tree", shapely.STRtree(geoms))
        object.__setattr__(self, "_zlo", np.array([-z.bottom for z in zs], dtype=float) - self.pad)
        object.__setattr__(self, "_zhi", np.minimum(np.array([-z.top for z in zs], dtype=float) + self.pad, 0.0)
                           if self.pad else np.array([-z.top for z in zs], dtype=float))
        object.__setattr__(self, "_h", h + self.pad)
        object.__setattr__(self, "_seabed", np.isfinite(h))
        object.__setattr__(self, "_bounds", shapely.bounds(geoms).reshape(-1, 4))
        object.__setattr__(self, "_rings", polygon_rings(geoms, self._centres))

    def _rasterise(self) -> None:
        """The broad phase's grid (:func:`.parts.rasterise`); the fine field is made when first used."""
        grid = rasterise(self._bounds, self._tree, self._zlo, self._zhi, self._h, self.terrain) if self.zones else None
        object.__setattr__(self, "_grid", grid)

    @property
    def _field(self) -> tuple[Any, ...]:
        """The fine lower-bound field (:func:`.parts.distance_field`: about 400 000 cells of two bytes in a plane
        per depth slab and one for every zone), made at its first use (the segment passes) and kept: a point
        query, as ``validate``'s start and goal, never needs it, nor its compiled kernel (issue 56).  A set
        derived with a smaller pad shares its parent's (:meth:`_derived`: its prisms, bands included, lie in the
        parent's, so the parent's slab planes bound its distances too)."""
        made: tuple[Any, ...] | None = self.__dict__.get("_fine")
        if made is None:
            parent = self.__dict__.get("_fine_of")
            assert self._grid is not None
            made = parent._field if parent is not None else distance_field(self._grid, self._rings, self._bounds)
            object.__setattr__(self, "_fine", made)
        return made

    def candidates(self, segments: ArrayLike) -> tuple[IntArray, IntArray]:
        """The broad phase: the (segment, zone) pairs the exact test must look at (:mod:`.broad`);
        every other pair provably does not meet.

        Parameters
        ----------
        segments : array_like
            Start and end points ``(N, 2, 3)`` (m).

        Returns
        -------
        seg, zone : numpy.ndarray of int
            The candidate pairs, sorted by segment.
        """
        if self._grid is None:
            return np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp)
        return self._candidates(segments, self._grid[8], self._grid[9])

    def _candidates(self, segments: ArrayLike, zlo: Any, zhi: Any) -> tuple[IntArray, IntArray]:
        """:meth:`candidates` with the bands ``zlo``/``zhi`` ``(Z,)`` (z up, m) in place of the grid's."""
        s = np.ascontiguousarray(np.asarray(segments, dtype=float).reshape(-1, 2, 3))
        if self._grid is None or s.shape[0] == 0:
            return np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp)
        x0, y0, cell, nx, ny, start, ids, box = self._grid[:8]
        args = (s, x0, y0, cell, nx, ny, start, ids, box, zlo, zhi, self._seabed, *self._rings)
        mark = np.full(len(self.zones), -1, dtype=np.intp)
        pairs = np.empty((2, 2 * s.shape[0] + 64), dtype=np.intp)
        m = candidates_kernel(*args, mark, pairs, pairs.shape[1])
        if m > pairs.shape[1]:  # more than the buffer held: again into one of the right size
            pairs = np.empty((2, m), dtype=np.intp)
            mark[:] = -1
            candidates_kernel(*args, mark, pairs, m)
        return pairs[0, :m], pairs[1, :m]

    def _lower_bound(self, p: FloatArray) -> FloatArray:
        """A lower bound of the horizontal distance from points ``(N, 3)`` to every footprint (m)."""
        assert self._grid is not None
        x0, y0, cell, nx, ny, *_, reach = self._grid
        fx, fy = (p[:, 0] - x0) / cell, (p[:, 1] - y0) / cell
        outside = np.hypot(np.maximum(np.maximum(-fx, fx - nx), 0.0), np.maximum(np.maximum(-fy, fy - ny), 0.0))
        i = np.clip(np.floor(fx).astype(int), 0, nx - 1)
        j = np.clip(np.floor(fy).astype(int), 0, ny - 1)
        inside: FloatArray = np.maximum(reach[j, i] - math.sqrt(2.0), 0.0)
        bound: FloatArray = np.where(outside > 0, outside, inside) * cell
        return bound

    def __len__(self) -> int:
        return len(self.zones)

    def with_pad(self, pad: float) -> Self:
        """The same zones grown by another pad.

        Parameters
        ----------
        pad : float
            Growth (m).

        Returns
        -------
        Zones
            The same class; ``self`` when ``pad`` is the current one.  A smaller pad is derived from this
            set (:meth:`_derived`: its cell lists and fine field shared, about a tenth of a build), a larger
            one built anew; either answers as a set built alone with that pad.
        """
        if pad == self.pad:
            return self
        if pad == 0.0:
            return self.exact
        if 0.0 < pad < self.pad:
            kept: dict[float, Self] = self.__dict__.setdefault("_smaller", {})
            if pad not in kept:
                derived = self._derived(pad)
                if derived is None:  # a grown footprint not inside this set's: built alone
                    derived = type(self)(self.zones, self.terrain, pad)
                kept[pad] = derived
            return kept[pad]
        return type(self)(self.zones, self.terrain, pad)

    @property
    def exact(self) -> Self:
        """The same zones without :attr:`pad`.

        Returns
        -------
        Zones
            ``self`` when unpadded.
        """
        if self.pad == 0:
            return self
        cached: Self | None = self.__dict__.get("_exact")
        if cached is None:
            cached = self._derived(0.0)
            assert cached is not None  # a footprint is inside its padded self
            object.__setattr__(self, "_exact", cached)
        return cached

    def _derived(self, pad: float) -> Self | None:
        """The set with a smaller pad (:attr:`exact` for 0) built from this one: its own footprints, bands,
        rings and R-tree (the exact tests and distances), the discs' centres shared, and the broad phase's cell
        lists and the fine field shared (this set's prisms hold the smaller ones: its cells are a superset and
        its distances lower bounds); only the grid's bands, which the compiled flat-band test uses exactly, are
        its own.  None when a footprint grown by ``pad`` is not inside this set's (mitred joins are checked,
        not assumed)."""
        out = object.__new__(type(self))
        for name, value in (("zones", self.zones), ("terrain", self.terrain), ("pad", pad),
                            ("_centres", self._centres)):
            object.__setattr__(out, name, value)
        footprints = np.array([z.footprint for z in self.zones], dtype=object)
        geoms = shapely.buffer(footprints, pad, join_style="mitre") if pad > 0 and self.zones else footprints
        if pad > 0 and self.zones and not bool(np.all(shapely.covers(self._geoms, geoms))):
            return None
        # the zones' own heights, not (h + pad) - pad: that is an ulp off (0.2 -> 0.19999999999999996), and the
        # exact set must answer at a band's face as a set built alone
        h = np.array([np.nan if z.above_seabed is None else z.above_seabed for z in self.zones], dtype=float)
        out._set_prisms(geoms, h)
        if self._grid is None:
            object.__setattr__(out, "_grid", None)
            return out
        sea = self._seabed
        # the highest seabed under its own box plus the height, as a set built alone has it (the padded top less
        # the pad is an ulp off, either way: a leg on the face was no candidate, or one an ulp above it was)
        top = band_tops(out._bounds, out._zhi, out._h, self.terrain)
        bottom = np.where(sea, -np.inf, out._zlo)
        object.__setattr__(out, "_grid", (*self._grid[:8], bottom, top, self._grid[10]))
        object.__setattr__(out, "_fine_of", self)  # this set's fine field, made when either first uses it
        return out

    @property
    def names(self) -> list[str]:
        """The zones' names in order.

        Returns
        -------
        list of str
            One name per zone.
        """
        return [z.name for z in self.zones]
