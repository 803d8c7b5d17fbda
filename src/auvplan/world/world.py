"""The world a mission takes place in: bounds, seabed, currents, obstacles and margins (the bounds and the
margins: :mod:`.limits`).

Every query is vectorised over points ``(..., 3)`` or segments ``(..., 2, 3)``.
The *clearance* of a point is the smallest slack over all constraints (m):
altitude above the seabed minus the minimum altitude, depth below the surface
minus the minimum depth, maximum depth minus depth, distance to each static
and moving obstacle surface minus the obstacle margin, and distance to the
bounds.  A point is free when its clearance is ≥ 0.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field

import numpy as np

from .._types import ArrayLike, BoolArray, FloatArray
from ..errors import DataError
from ..geometry import as_points
from ..runtime.jit import jit_enabled
from .currents.fields import CurrentField, UniformCurrent
from .kernels.box import segments_in_box
from .land import Land
from .limits import Bounds, Margins
from .moving import MovingObstacle
from .obstacles import Ellipsoid, Shape
from .terrain import Terrain
from .zones import Zones

__all__ = ["Bounds", "Margins", "World"]


@dataclass(frozen=True, eq=False)
class World:
    """Everything static or scripted about the environment.

    Parameters
    ----------
    bounds : Bounds
        Operating area; must lie inside the terrain's extent and the current grid.
    terrain : Terrain or None
        Seabed; ``None`` for open water (flow and tracking scenes).
    currents : CurrentField
        Ocean current.
    obstacles : tuple of Shape
        Static obstacles.
    moving : tuple of MovingObstacle
        Scripted moving obstacles.
    margins : Margins
        Vehicle safety margins.
    origin : (lat, lon) or None
        Geographic position of the local origin, for exports.
    name : str
        Free text.
    land : Land or None
        Land polygons (coastlines).  The terrain is raised above the surface on every cell that
        touches land (:meth:`Land.burn`), so the cost, the planners and the simulator keep off it;
        :meth:`is_free` and :meth:`segments_free` also test the polygons exactly.
    zones : Zones or None
        Charted no-go prisms (cables, wrecks, restricted areas …): :meth:`segments_free` tests them
        exactly (:meth:`Zones.entries`) and :meth:`clearances` reports the distance to them.

    Raises
    ------
    DataError
        If the terrain or the current field does not cover the bounds, or land comes without terrain.
    """

    bounds: Bounds
    terrain: Terrain | None = None
    currents: CurrentField = field(default_factory=UniformCurrent)
    obstacles: tuple[Shape, ...] = ()
    moving: tuple[MovingObstacle, ...] = ()
    margins: Margins = field(default_factory=Margins)
    origin: tuple[float, float] | None = None
    name: str = ""
    land: Land | None = None
    zones: Zones | None = None

    def __post_init__(self) -> None:
        if self.land is not None:
            if self.terrain is None:
                raise DataError(f"world {self.name!r}: land polygons need a terrain grid to be burnt into")
            if not self.land.is_empty:
                object.__setattr__(self, "terrain", self.land.burn(self.terrain))
        object.__setattr__(self, "obstacles", tuple(self.obstacles))
        object.__setattr__(self, "moving", tuple(self.moving))
        b = self.bounds
        if self.terrain is not None:
            x0, x1, y0, y1 = self.terrain.extent
            tol = 1e-6 * max(x1 - x0, y1 - y0)
            if b.xmin < x0 - tol or b.xmax > x1 + tol or b.ymin < y0 - tol or b.ymax > y1 + tol:
                raise DataError(
                    f"world {self.name!r}: bounds x [{b.xmin:.0f}, {b.xmax:.0f}] y [{b.ymin:.0f}, {b.ymax:.0f}] "
                    f"are not covered by the terrain extent x [{x0:.0f}, {x1:.0f}] y [{y0:.0f}, {y1:.0f}]"
                )
        if not self.currents.covers(b.xmin, b.xmax, b.ymin, b.ymax):
            raise DataError(
                f"world {self.name!r}: the current field does not cover the bounds "
                f"x [{b.xmin:.0f}, {b.xmax:.0f}] y [{b.ymin:.0f}, {b.ymax:.0f}]"
            )

    # ------------------------------------------------------------------ point queries
    def seabed(self, x: ArrayLike, y: ArrayLike) -> FloatArray:
        """Seabed elevation.

        Parameters
        ----------
        x, y : array_like
            Easting and northing (m); broadcast together.

        Returns
        -------
        numpy.ndarray
            Elevation (m, positive up); ``-inf`` where there is no terrain.
        """
        if self.terrain is None:
            return np.full(np.broadcast(np.asarray(x), np.asarray(y)).shape, -np.inf)
        return self.terrain.elevation(x, y)

    def clearances(self, points: ArrayLike, t: float = 0.0, moving: bool = True) -> dict[str, FloatArray]:
        """Every constraint's slack at points (m; ≥ 0 is satisfied).

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).
        t : float, default 0.0
            Time at which the moving obstacles are placed (s).
        moving : bool, default True
            Whether to include the moving obstacles.

        Returns
        -------
        dict of str to numpy.ndarray
            Keys ``altitude``, ``surface``, ``max_depth``, ``bounds``, ``obstacles`` (static),
            ``moving``, ``land`` (horizontal distance to the shoreline, negative on land) and ``zones``
            (:meth:`Zones.signed_distance`, negative inside a zone), each ``(...)`` (m).  Missing
            constraints are ``+inf``.
        """
        p = as_points(points)
        m = self.margins
        if self.terrain is None:
            altitude = np.full(p.shape[:-1], np.inf)
        else:
            altitude = self.terrain.altitude(p) - m.min_altitude
        return self._clearances(p, altitude, t, moving)

    def clearly_free(self, point: ArrayLike, t: float = 0.0) -> bool:
        """Whether :meth:`explain` would find nothing at ``point``, decided with the seabed in numpy.

        Every slack but the seabed's and an ellipsoid's is the one :meth:`clearances` computes; the
        altitude comes from :meth:`Terrain.elevation_bounds` and must exceed its bound, so that the
        compiled seabed cannot put the point below ``min_altitude``; an ellipsoid's distance is its
        :meth:`~Ellipsoid.lower_bound_distance` less a micrometre per metre of its size (the exact one
        is a compiled foot-point search).  False says only "not clearly": ask :meth:`explain`.
        ``validate`` checks its start and goal so without loading a compiled kernel (issue 56).

        Parameters
        ----------
        point : array_like
            One point ``(3,)`` (m).
        t : float, default 0.0
            Time at which the moving obstacles are placed (s).

        Returns
        -------
        bool
            True when every slack is ≥ 0 with the seabed's rounding to spare.
        """
        p = as_points(np.asarray(point, dtype=float))
        if p.shape != (3,) or not np.all(np.isfinite(p)):
            return False
        altitude = np.asarray(np.inf)
        if self.terrain is not None:
            zb, err = self.terrain.elevation_bounds(p[0], p[1])
            altitude = p[2] - zb - self.margins.min_altitude - err
        return all(float(v) >= 0.0 for v in self._clearances(p, altitude, t, True, _lower_distance).values())

    def _clearances(self, p: FloatArray, altitude: FloatArray, t: float, moving: bool,
                    distance: Callable[[Shape, FloatArray], FloatArray] | None = None) -> dict[str, FloatArray]:
        """:meth:`clearances` of the points ``p (..., 3)`` given their altitude slack (and the obstacles'
        distance, by default each shape's own)."""
        shape = p.shape[:-1]
        m = self.margins
        out: dict[str, FloatArray] = {"altitude": altitude}
        out["surface"] = -p[..., 2] - m.min_depth
        out["max_depth"] = m.max_depth + p[..., 2]
        out["bounds"] = self.bounds.slack(p)
        out["obstacles"] = self._obstacle_slack(self.obstacles, p, distance)
        if moving:
            shapes = tuple(o.at(t) for o in self.moving if o.active(t))
            out["moving"] = self._obstacle_slack(shapes, p, distance)
        else:
            out["moving"] = np.full(shape, np.inf)
        out["land"] = np.full(shape, np.inf) if self.land is None else self.land.signed_distance(p)
        out["zones"] = np.full(shape, np.inf) if not self.zones else self.zones.signed_distance(p)
        return out

    def _obstacle_slack(self, shapes: Iterable[Shape], p: FloatArray,
                        distance: Callable[[Shape, FloatArray], FloatArray] | None = None) -> FloatArray:
        d = np.full(p.shape[:-1], np.inf)
        for s in shapes:
            d = np.minimum(d, (s.distance(p) if distance is None else distance(s, p)) - self.margins.obstacle)
        return d

    def clearance(self, points: ArrayLike, t: float = 0.0, moving: bool = True) -> FloatArray:
        """Smallest constraint slack at points.

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).
        t : float, default 0.0
            Time at which the moving obstacles are placed (s).
        moving : bool, default True
            Whether to include the moving obstacles.

        Returns
        -------
        numpy.ndarray
            Least slack over :meth:`clearances` ``(...)`` (m); free where ≥ 0.
        """
        c = self.clearances(points, t, moving)
        least: FloatArray = np.minimum.reduce(list(c.values()))
        return least

    def is_free(self, points: ArrayLike, t: float = 0.0, moving: bool = True) -> BoolArray:
        """Where every constraint holds.

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).
        t : float, default 0.0
            Time at which the moving obstacles are placed (s).
        moving : bool, default True
            Whether to include the moving obstacles.

        Returns
        -------
        numpy.ndarray of bool
            ``(...)``, True where the clearance is ≥ 0.
        """
        return self.clearance(points, t, moving) >= 0.0

    def explain(self, point: ArrayLike, t: float = 0.0) -> str:
        """Human-readable reason why a point is not free.

        Parameters
        ----------
        point : array_like
            One point ``(3,)`` (m).
        t : float, default 0.0
            Time at which the moving obstacles are placed (s).

        Returns
        -------
        str
            The violated constraints with their slack, ``"; "``-separated; ``""`` when the point is free.
        """
        c = {k: float(v) for k, v in self.clearances(np.asarray(point, dtype=float), t).items()}
        words = {
            "altitude": f"closer than min_altitude {self.margins.min_altitude:g} m to the seabed",
            "surface": f"shallower than min_depth {self.margins.min_depth:g} m",
            "max_depth": f"deeper than max_depth {self.margins.max_depth:g} m",
            "bounds": "outside the bounds",
            "obstacles": f"within {self.margins.obstacle:g} m of a static obstacle",
            "moving": f"within {self.margins.obstacle:g} m of a moving obstacle",
            "land": "on land" + (f" ({self.land.name})" if self.land is not None and self.land.name else ""),
            "zones": "inside a no-go zone" + (f" ({self.zone_at(point)})" if self.zones else ""),
        }
        bad = [f"{words[k]} (slack {v:.2f} m)" for k, v in c.items() if v < 0]
        return "; ".join(bad)

    # ------------------------------------------------------------------ segment queries
    def segments_free(self, segments: ArrayLike, t: float = 0.0, moving: bool = True, *,
                      ends_free: bool = False,
                      end_altitudes: tuple[ArrayLike, ArrayLike] | None = None) -> BoolArray:
        """Where whole segments satisfy every constraint.

        The seabed is tested exactly (:meth:`Terrain.segment_min_altitude`); depth
        limits and bounds are convex, so the end points decide; obstacles use their
        exact (sphere) or conservative (ellipsoid with margin) segment tests.

        Parameters
        ----------
        segments : array_like
            Start and end points ``(..., 2, 3)`` (m).
        t : float, default 0.0
            Time at which the moving obstacles are frozen (s).
        moving : bool, default True
            Whether to include the moving obstacles.
        ends_free : bool, default False
            The caller knows both ends are free points (the convex tests are skipped).
        end_altitudes : tuple of array_like, optional
            ``(g_a, g_b)``, the ends' altitudes above the seabed (m) when already known.

        Returns
        -------
        numpy.ndarray of bool
            ``(...)``, True for free segments.

        Raises
        ------
        ValueError
            If ``segments`` is not of shape ``(..., 2, 3)``.
        """
        s = np.asarray(segments, dtype=float)
        if s.shape[-2:] != (2, 3):
            raise ValueError(f"segments must have shape (..., 2, 3), got {s.shape}")
        m = self.margins
        if ends_free:
            ok = np.ones(s.shape[:-2], dtype=bool)
        else:
            ok = self._ends_inside(s)
        if self.terrain is not None:
            alt = self.terrain.segment_min_altitude(s, threshold=m.min_altitude, end_altitudes=end_altitudes)
            ok &= alt >= m.min_altitude
        shapes = list(self.obstacles)
        if moving:
            shapes += [o.at(t) for o in self.moving if o.active(t)]
        for shape in shapes:
            ok &= ~shape.segments_hit(s, m.obstacle)
        if self.land is not None and ok.any():  # exact polygon test (implied by the burnt terrain)
            flat = np.array(ok, dtype=bool).reshape(-1)
            idx = np.flatnonzero(flat)
            flat[idx] = ~self.land.segments_hit(s.reshape(-1, 2, 3)[idx])
            ok = flat.reshape(np.shape(ok))
        if self.zones and ok.any():  # exact segment-vs-prism test of the charted zones
            flat = np.array(ok, dtype=bool).reshape(-1)
            idx = np.flatnonzero(flat)
            flat[idx] = ~self.zones.segments_enter(s.reshape(-1, 2, 3)[idx])
            ok = flat.reshape(np.shape(ok))
        return ok

    def _ends_inside(self, s: FloatArray) -> BoolArray:
        """Where both ends of the segments ``s (..., 2, 3)`` are in the depth band and the bounds (convex: the
        whole segment is then), compiled (:mod:`auvplan.world.kernels.box`; numpy's comparisons without numba)."""
        m, b = self.margins, self.bounds
        if not jit_enabled():
            z = s[..., 2]
            ok: BoolArray = np.all(-z >= m.min_depth, axis=-1) & np.all(-z <= m.max_depth, axis=-1)
            return ok & b.contains(s).all(axis=-1)
        inside = np.empty(s.shape[:-2], dtype=bool)
        segments_in_box(np.ascontiguousarray(s.reshape(-1, 2, 3)), float(m.min_depth), float(m.max_depth),
                        np.array([b.xmin, b.xmax, b.ymin, b.ymax, b.zmin, b.zmax], dtype=float), inside.reshape(-1))
        return inside

    def zone_at(self, point: ArrayLike) -> str:
        """The names of the zones a point is inside (for messages).

        Parameters
        ----------
        point : array_like
            One point ``(3,)`` (m).

        Returns
        -------
        str
            Comma-separated names; ``""`` outside every zone.
        """
        if not self.zones:
            return ""
        p = np.asarray(point, dtype=float).reshape(1, 3)
        _, zi = self.zones.entries(np.stack([p, p], axis=1))
        return ", ".join(self.zones.names[j] for j in zi)

    def path_free(self, points: ArrayLike, t: float = 0.0, moving: bool = False) -> bool:
        """Whether the polyline through the points is free everywhere.

        Parameters
        ----------
        points : array_like
            Vertices ``(N, 3)`` (m).
        t : float, default 0.0
            Time at which the moving obstacles are frozen (s).
        moving : bool, default False
            Whether to include the moving obstacles.

        Returns
        -------
        bool
            True when every segment (or the single point) is free.
        """
        p = as_points(points)
        if p.shape[0] < 2:
            return bool(self.is_free(p, t, moving).all())
        return bool(self.segments_free(np.stack([p[:-1], p[1:]], axis=1), t, moving).all())


def _lower_distance(shape: Shape, p: FloatArray) -> FloatArray:
    """A shape's distance, or for an ellipsoid a lower bound of it found without a compiled kernel, less its
    rounding (:meth:`World.clearly_free`)."""
    if isinstance(shape, Ellipsoid):
        lower: FloatArray = shape.lower_bound_distance(p) - 1e-6 * (1.0 + shape.bounding_radius)
        return lower
    return shape.distance(p)
