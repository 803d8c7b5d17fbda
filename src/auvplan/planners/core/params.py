"""The methods' settings in one place (the scenario's ``[planner.flow]``, ``[planner.grid]`` and
``[planner.timeopt]`` tables), below :class:`~auvplan.planners.core.base.PlannerSpec` that holds them and the
method packages that read them.  The swarm optimisers' settings live with them in :mod:`auvplan.optim`."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["FlowParams", "GridParams", "TimeoptParams"]


@dataclass(frozen=True)
class FlowParams:
    """Settings of the streamline planner.

    Attributes
    ----------
    field : str
        ``"exact"`` (Weiss image, default), ``"document"`` (sink + θ-dependent dipole) or ``"uniform"``
        (uniform flow + dipole, the baseline of document 000's Fig. 5: spheres only, no fixed goal).
    rankine : str
        How the body round an ellipsoid is sized: ``"line"`` (default: a fitted line distribution of
        sources and sinks, the smallest containing body found), ``"pair"`` (source/sink pair, strength
        and half-spacing both free) or ``"document"`` (document 000's: stagnation point and mid-radius
        equal to the semi-axes; the ellipsoid is not contained).
    weights : str
        ``"normalised"`` (default) or ``"document"`` (product weights).
    distance : str
        ``"true"`` (default) or ``"ray"`` (document's ellipsoid distance) for the weights.
    strength : float
        Sink strength m at the target (the streamlines' shape does not depend on it for spheres).
    h_min, h_max : float
        Step bounds (m); ``h_min = 0`` means 0.05 × the smallest obstacle size (docs/methods.md §1.6).
        The step is also at most ``step_factor`` × the clearance and × the distance to the goal.
    step_factor : float
        Step as a fraction of the clearance to the nearest surface (or of the goal distance).
    arrive : float
        Arrival radius about the goal (m).
    max_steps : int
        Step limit per streamline.
    stagnation : float
        |u| below this fraction of the bare sink's speed at the same point is a stagnation event.
    path : str
        ``"flyable"`` (default): the path of a vehicle that steers by the flow's direction and turns by at
        most 1/R per metre (R the problem's vehicle turn radius; :mod:`auvplan.planners.flow.turning`),
        every leg checked exactly; ``INFEASIBLE`` where it cannot follow the flow within the clearance.
        ``"streamline"``: the pure streamline (document 000), whatever its turns.  Without a turn radius
        in the problem both are the streamline.
    """

    field: str = "exact"
    rankine: str = "ellipsoid"
    weights: str = "normalised"
    distance: str = "true"
    strength: float = 1.0
    h_min: float = 0.0
    h_max: float = float("inf")
    step_factor: float = 0.5
    arrive: float = 0.5
    max_steps: int = 4000
    stagnation: float = 1e-6
    path: str = "flyable"

    def __post_init__(self) -> None:
        if self.path not in ("flyable", "streamline"):
            raise ValueError(f"path = {self.path!r}: choose 'flyable' or 'streamline'")
        if self.field not in ("exact", "document", "uniform"):
            raise ValueError(f"field = {self.field!r}: choose 'exact', 'document' or 'uniform'")
        if self.rankine not in ("line", "pair", "document", "ellipsoid"):
            raise ValueError(f"rankine = {self.rankine!r}: choose 'line', 'pair', 'document' or 'ellipsoid'")
        if self.weights not in ("normalised", "document"):
            raise ValueError(f"weights = {self.weights!r}: choose 'normalised' or 'document'")
        if self.distance not in ("true", "ray"):
            raise ValueError(f"distance = {self.distance!r}: choose 'true' or 'ray'")
        if not (0 <= self.h_min <= self.h_max) or not self.arrive > 0 or self.max_steps < 1 or self.strength <= 0 \
                or not 0 < self.step_factor <= 1:
            raise ValueError("need 0 < h_min <= h_max, arrive > 0, max_steps >= 1 and strength > 0")


@dataclass(frozen=True)
class GridParams:
    """Settings of the lattice reference planner (``[planner.grid]``).

    Attributes
    ----------
    cell : float
        Horizontal cell size (m); 0 = ``max(terrain spacing, (volume / target_nodes)^(1/3))``.
    cell_z : float
        Vertical cell size (m); 0 = ``cell``, or finer where the depth band would hold fewer
        than ``levels`` levels.
    levels : int
        Fewest depth levels of an automatic vertical cell.
    target_nodes : int
        Node count the automatic cell size aims at.
    max_nodes : int
        Refuse lattices larger than this (memory guard: the reference's peak is about 42 bytes a node
        plus 13 MB; :func:`auvplan.io.files.limits.lattice_bytes` estimates it).
    objective : str
        ``"cost"`` (length and energy terms of the planner's cost function, default) or ``"length"``.
    relax_iterations : int
        Most elastic-band sweeps per refinement level (0 = none).
    smooth : bool
        Try a clamped cubic B-spline over the shortened path; kept only when free and cheaper.
    converge : bool
        Refine the lattice path to convergence (cycles of elastic-band levels from 1/8 to 1/2048
        of the path, until a cycle gains less than ``converge_tol``) instead of the band alone:
        the reference becomes the best known plan, not a lattice bound.
    converge_tol : float
        Relative cost gain below which the refinement stops.
    ladder : bool
        With ``converge``: also plan on the lattices 2, 4, … times coarser (up to 1/25 of the
        search box's narrower side) and keep the cheapest, so that halving the cell never gives
        a worse reference.
    any_angle : int
        Longest any-angle link of the lattice search in cells on each axis (lazy Theta*,
        :mod:`auvplan.planners.grid.anyangle`): a node links straight to a node up to this far
        when the node fields clear the segment, so the cost-to-go is not bound to the 26 lattice
        directions (16: within 0.8 % of the straight-line distance in open water, ``tests/oracles/test_grid.py``);
        0 (default) = the 26 directions only (metricated: up to 8 % long).  Off by default: on the
        sphere scene of ``tests/oracles/test_grid.py`` the refinement of the any-angle lattice path settles
        0.2 % above the geodesic (the conservative clearance test sends it round another side),
        where the 26-direction path refines to it within 10⁻⁵ (``docs/lattice.md``).
    also_any_angle : int
        With ``converge``: every lattice of the ladder is also searched with any-angle links of this
        many cells, both lattice paths are screened by a short refinement and the cheaper is refined
        to convergence (:mod:`auvplan.planners.grid.ladder`), so that a finer cell can lower the
        reference where the 26 directions alone stall (``docs/lattice.md``); 0 = the links of
        ``any_angle`` alone.  The swarms' seeding lattice uses ``any_angle`` alone.

    Raises
    ------
    ValueError
        If a setting is outside its range.
    """

    cell: float = 0.0
    cell_z: float = 0.0
    levels: int = 10
    target_nodes: int = 500_000
    max_nodes: int = 4_000_000
    objective: str = "cost"
    relax_iterations: int = 200
    smooth: bool = True
    converge: bool = True
    converge_tol: float = 1e-5
    ladder: bool = True
    any_angle: int = 0
    also_any_angle: int = 16

    def __post_init__(self) -> None:
        if self.any_angle < 0:
            raise ValueError(f"any_angle = {self.any_angle}: must be >= 0 (0 = the 26 lattice directions only)")
        if self.also_any_angle < 0:
            raise ValueError(f"also_any_angle = {self.also_any_angle}: must be >= 0 (0 = the any_angle links alone)")
        if not 0.0 < self.converge_tol < 1.0:
            raise ValueError(f"converge_tol = {self.converge_tol}: must be in (0, 1)")
        if self.cell < 0 or self.cell_z < 0:
            raise ValueError("cell and cell_z must be >= 0 (0 = automatic)")
        if self.levels < 2:
            raise ValueError(f"levels = {self.levels}: must be >= 2")
        if self.target_nodes < 8 or self.max_nodes < self.target_nodes:
            raise ValueError("need target_nodes >= 8 and max_nodes >= target_nodes")
        if self.objective not in ("cost", "length"):
            raise ValueError(f"objective = {self.objective!r}: choose 'cost' or 'length'")
        if self.relax_iterations < 0:
            raise ValueError("relax_iterations must be >= 0")


@dataclass(frozen=True)
class TimeoptParams:
    """Settings of the time-optimal planner in currents that change with time.

    Attributes
    ----------
    objective : str
        ``"time"`` (earliest arrival at the vehicle's speed) or ``"energy"`` (least energy over
        the through-water speeds ``speeds`` × the vehicle's speed, each time-optimal).
    depart_s : float
        Departure time (s after the mission's ``start_time``).
    cell : float
        Horizontal lattice cell (m); 0 = 1/100 of the larger horizontal side of the search box.
    levels : int
        Depth levels of the lattice across the allowed depth band (1 = the start's depth only).
    dt : float
        Time step of the current table the search reads (s).
    horizon_s : float
        Longest mission the table covers (s); 0 = 1.5 × the still-water straight-line time + 2 h
        (doubled, up to twice, when a plan runs past it).
    substep : float
        Longest sub-step of the travel-time integration along a segment (m); 0 = cell / 2.
    relax_iterations : int
        Sweeps of the time-aware elastic band after the lattice search (0 = none).
    speeds : tuple of float
        Fractions of the vehicle's speed tried by the ``"energy"`` objective.
    labels : str
        Lattice search: ``"auto"`` (one arrival label per node where the current stays slower than
        the vehicle, else one per node and arrival-time bucket), ``"single"`` or ``"multi"``.
    label_dt : float
        Bucket width of the multi-label search (s); 0 = a cell's still-water leg time.
    max_labels : int
        Most labels of the multi-label search (the bucket width grows to stay within it).
    tail_first : bool
        Let the multi-label search also fly a leg tail-first (heading against its line, carried along
        it by a current stronger than the vehicle; docs/timeopt.md).
    method : str
        ``"front"`` (the reachable set's front on a horizontal grid, backtracked and refined by
        Zermelo's heading equation; the lattice search when it finds no flyable path) or
        ``"lattice"`` (the lattice search alone).
    headings : int
        Headings tried per node and step by the front (and one more at the parabola's vertex).
    """

    objective: str = "time"
    depart_s: float = 0.0
    cell: float = 0.0
    levels: int = 5
    dt: float = 600.0
    horizon_s: float = 0.0
    substep: float = 0.0
    relax_iterations: int = 60
    speeds: tuple[float, ...] = (0.5, 0.6, 0.7, 0.8, 0.9, 1.0)
    labels: str = "auto"
    label_dt: float = 0.0
    max_labels: int = 4_000_000
    tail_first: bool = False
    method: str = "front"
    headings: int = 16

    def __post_init__(self) -> None:
        if self.method not in ("front", "lattice"):
            raise ValueError(f"method = {self.method!r}: choose 'front' or 'lattice'")
        if not abs(self.depart_s) <= 366 * 86400.0:  # as --depart-between's offsets; 1e14 s: a year 3170900 tide
            raise ValueError(f"depart_s = {self.depart_s:g} s: must lie within 366 d of [mission] start_time")
        if not 4 <= self.headings <= 360:  # 1e9 allocated its sines and cosines: 16 GB, a minute of swapping
            raise ValueError(f"headings = {self.headings}: must lie in [4, 360] (360: a heading every degree)")
        if self.labels not in ("auto", "single", "multi"):
            raise ValueError(f"labels = {self.labels!r}: choose 'auto', 'single' or 'multi'")
        if self.label_dt < 0 or self.max_labels < 1:
            raise ValueError("label_dt must be >= 0 (0 = automatic) and max_labels >= 1")
        if self.objective not in ("time", "energy"):
            raise ValueError(f"objective = {self.objective!r}: choose 'time' or 'energy'")
        if self.cell < 0 or self.substep < 0 or self.horizon_s < 0:
            raise ValueError("cell, substep and horizon_s must be >= 0 (0 = automatic)")
        if self.levels < 1:
            raise ValueError(f"levels = {self.levels}: must be >= 1")
        if not self.dt > 0:
            raise ValueError(f"dt = {self.dt}: must be > 0")
        if self.relax_iterations < 0:
            raise ValueError("relax_iterations must be >= 0")
        if not self.speeds or any(not 0.0 < s <= 1.0 for s in self.speeds):
            raise ValueError(f"speeds = {list(self.speeds)}: fractions in (0, 1]")
