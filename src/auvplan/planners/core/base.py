"""Planning problem, planner settings and the result every planner returns."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, TypeAlias

import numpy as np

from ..._types import BoolArray, FloatArray, Status
from ...optim.bee import ABCParams, IABCParams
from ...optim.de import DEParams
from ...optim.ga import GAParams
from ...optim.local import PatternParams
from ...optim.pso import PSOParams
from ...path.flyable import VehicleLimits
from ...world import World
from .params import FlowParams, GridParams, TimeoptParams
from .registry import PIPELINES, PLANNERS, SWARM, get, known, names

__all__ = ["PlannerSpec", "PlanningProblem", "PlanResult", "PIPELINES", "PLANNERS", "SWARM", "Progress"]

#: ``progress(iteration, best_cost)``, called by the iterating planners after each iteration.
Progress: TypeAlias = Callable[[int, float], None]



@dataclass(frozen=True)
class PlannerSpec:
    """Settings of the global planner (the scenario's ``[planner]`` table).

    Attributes
    ----------
    name : str
        ``iabc``, ``abc``, ``ga``, ``pso`` (swarm, document 002), ``de`` (scipy's differential
        evolution), ``flow`` (streamlines, document 000), ``grid`` (lattice reference), ``timeopt``
        (time-optimal in currents), or any planner registered with
        :func:`auvplan.planners.core.registry.register`.
    pipeline : str
        For the population optimisers: ``"seeded"`` (default: a coarse lattice path, fitted as
        control points, seeds part of the first population; the best plan is refined by a
        pattern search that keeps the exact test; the lattice path is returned when the
        optimiser found no feasible one), ``"document"`` (the algorithm alone) or
        ``"progressive"`` (the algorithm alone, coarse to fine: ``coarse_fraction`` of the budget
        with ``⌈K/2⌉`` control points, whose best paths, refitted to K control points, seed the
        rest; :mod:`auvplan.planners.swarm.progressive`).
    seed_fraction : float
        Share of the first population seeded from the lattice path: the best, by the objective
        (evaluations counted), of the path's least-squares fits and of the control points repeated
        at the corners of its taut polygon (:func:`auvplan.planners.swarm.seeding.lattice_seeds`).
    refine_fraction : float
        Share of the evaluation budget kept for the refinement.
    polish : int
        Relaxation sweeps per level of the seeded pipeline's last stage, the plan polished as a
        polyline by the lattice's band (:mod:`auvplan.planners.swarm.polish`; not counted in the
        budget, its CPU reported in ``PlanResult.work``); 0: no polish (the pipeline before #35).
    seed_nodes : int
        Node count of the coarse seeding lattice.
    coarse_fraction : float
        Share of the budget the ``"progressive"`` pipeline spends with ``⌈K/2⌉`` control points.
    bend : float
        Weight of the bends in the ``"progressive"`` pipeline's refit (0: the plain least-squares
        fit at uniform arc length; :func:`auvplan.planners.swarm.seeding.fit_control_points`).
    population : int
        Food sources / individuals / particles.
    iterations : int
        Iteration cap of the ``"document"`` pipeline without a budget (document 002: IterMax = 100).
    budget : int
        Objective evaluations, spent exactly by every optimiser (the last batch truncated);
        0 means ``population * iterations`` in the seeded and progressive pipelines, and the iteration cap
        alone (as in document 002) in the document pipeline.
    control_points : int
        Free interior B-spline control points K, 2 ≤ K ≤ 50 (the clamped cubic spline needs 4 with the
        start and the goal).
    samples : int
        Samples per path for the cost.
    energy : str
        ``"physical"`` (default), ``"document"`` (document 002 eq. 17, V_oc the current's speed) or
        ``"document-vehicle"`` (eq. 17 with V_oc the vehicle's still-water speed, the document's gloss).
    w_length, w_terrain, w_energy : float
        Weights of the three cost terms (document 002 eq. 9 uses 1, 1, 1).
    terrain_penalty : float
        Document 002's M, per sample below the seabed (m of equivalent length);
        auvplan adds ``terrain_penalty`` per metre of violation depth as well.
    energy_scale : float
        Cost units per joule; 0 (default) = metres of still-water travel per joule at
        cruise speed, so the energy term reads as equivalent metres.
    abc, iabc, ga, pso, de : ABCParams, IABCParams, GAParams, PSOParams, DEParams
        Settings of each population optimiser.
    refine : PatternParams
        Settings of the seeded pipeline's pattern search.
    flow : FlowParams
        Settings of the streamline planner.
    grid : GridParams
        Settings of the lattice reference planner.
    timeopt : TimeoptParams
        Settings of the time-optimal planner.
    robust : str
        With ``[currents] members`` (issue 39): ``"none"`` plans on the nominal field; ``"p90"``
        plans one route for all members with the least 90th-percentile arrival time, ``"success"``
        with the highest success probability (:mod:`auvplan.sim.ensemble.robust`).
    _plugins : tuple of (str, object)
        Settings of planners registered from outside the package, by name (each read from the
        scenario's ``[planner.<name>]`` table into its registered settings type); use
        :meth:`params_for`.

    Raises
    ------
    ValueError
        If a setting is outside its range or names an unknown planner or pipeline.
    """

    name: str = "iabc"
    pipeline: str = "seeded"
    seed_fraction: float = 0.2
    refine_fraction: float = 0.2
    polish: int = 2
    seed_nodes: int = 8_000
    coarse_fraction: float = 0.2
    bend: float = 1.0
    population: int = 50
    iterations: int = 100
    budget: int = 0
    control_points: int = 6
    samples: int = 200
    energy: str = "physical"
    w_length: float = 1.0
    w_terrain: float = 1.0
    w_energy: float = 1.0
    terrain_penalty: float = 1.0e4
    energy_scale: float = 0.0
    abc: ABCParams = field(default_factory=ABCParams)
    iabc: IABCParams = field(default_factory=IABCParams)
    ga: GAParams = field(default_factory=GAParams)
    pso: PSOParams = field(default_factory=PSOParams)
    de: DEParams = field(default_factory=DEParams)
    refine: PatternParams = field(default_factory=PatternParams)
    flow: FlowParams = field(default_factory=FlowParams)
    grid: GridParams = field(default_factory=GridParams)
    timeopt: TimeoptParams = field(default_factory=TimeoptParams)
    robust: str = "none"
    _plugins: tuple[tuple[str, Any], ...] = ()

    def __post_init__(self) -> None:
        if not known(self.name):
            raise ValueError(f"name = {self.name!r}: choose one of {', '.join(names())}")
        if self.pipeline not in PIPELINES:
            raise ValueError(f"pipeline = {self.pipeline!r}: choose one of {', '.join(PIPELINES)}")
        if not 0.0 <= self.seed_fraction <= 0.5:
            raise ValueError(f"seed_fraction = {self.seed_fraction}: must lie in [0, 0.5]")
        if not 0.0 <= self.refine_fraction < 1.0:
            raise ValueError(f"refine_fraction = {self.refine_fraction}: must lie in [0, 1)")
        if not 0.0 < self.coarse_fraction < 1.0:
            raise ValueError(f"coarse_fraction = {self.coarse_fraction}: must lie in (0, 1)")
        if self.bend < 0:
            raise ValueError(f"bend = {self.bend}: must be >= 0")
        if self.polish < 0:
            raise ValueError(f"polish = {self.polish}: must be >= 0")
        if self.seed_nodes < 1000:
            raise ValueError(f"seed_nodes = {self.seed_nodes}: must be >= 1000")
        if self.population < 4:
            raise ValueError(f"population = {self.population}: must be >= 4")
        if self.iterations < 1 or self.budget < 0:
            raise ValueError("iterations must be >= 1 and budget >= 0")
        if not 2 <= self.control_points <= 50:
            raise ValueError(f"control_points = {self.control_points}: must lie in [2, 50] (a clamped cubic "
                             "B-spline needs 4 control points with the start and the goal)")
        if self.samples < 10:
            raise ValueError(f"samples = {self.samples}: must be >= 10")
        if self.energy not in ("physical", "document", "document-vehicle"):
            raise ValueError(f"energy = {self.energy!r}: choose 'physical', 'document' or 'document-vehicle'")
        for k in ("w_length", "w_terrain", "w_energy", "terrain_penalty", "energy_scale"):
            if getattr(self, k) < 0:
                raise ValueError(f"{k} = {getattr(self, k)}: must be >= 0")
        if self.robust not in ("none", "p90", "success"):
            raise ValueError(f"robust = {self.robust!r}: choose 'none', 'p90' or 'success'")

    def params_for(self, name: str | None = None) -> Any:
        """The settings of a planner: its table of this spec, or its registered type's defaults.

        Parameters
        ----------
        name : str, optional
            Planner name (default: this spec's).

        Returns
        -------
        object or None
            ``self.flow`` for ``flow``, ``self.iabc`` for ``iabc`` …; for a planner registered from
            outside, the settings read from ``[planner.<name>]``, else its settings type's defaults;
            None for a planner without settings.
        """
        entry = get(name or self.name)
        if entry.table is not None:
            return getattr(self, entry.table)
        for key, value in self._plugins:
            if key == entry.name:
                return value
        cls = entry.settings_type
        return cls() if cls is not None else None

    @property
    def evaluations(self) -> int:
        """The evaluation budget in force.

        Returns
        -------
        int
            ``budget``, or ``population * iterations`` when it is 0.
        """
        return self.budget or self.population * self.iterations


@dataclass(frozen=True, eq=False)
class PlanningProblem:
    """What a global planner needs: the world, the end points and the vehicle's energy model.

    Attributes
    ----------
    world : World
        Environment (seabed, currents, obstacles, margins).
    start, goal : ndarray, shape (3,)
        End points (m).
    speed : float
        Through-water speed of the vehicle (m/s).
    hotel_power : float
        Power drawn regardless of speed (W).
    drag_k : float
        Propulsion power coefficient k in ``P = k V³`` (W s³/m³).
    limits : VehicleLimits or None
        Pitch, turn radius and depth rating every result is held to
        (:func:`auvplan.planners.core.vehicle_limits.enforce_limits`); None: not checked.

    Raises
    ------
    ValueError
        If the speed is not positive.
    """

    world: World
    start: FloatArray
    goal: FloatArray
    speed: float = 1.5
    hotel_power: float = 15.0
    drag_k: float = 5.8
    limits: VehicleLimits | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "start", np.asarray(self.start, dtype=float).reshape(3))
        object.__setattr__(self, "goal", np.asarray(self.goal, dtype=float).reshape(3))
        if not self.speed > 0:
            raise ValueError(f"speed must be positive, got {self.speed}")


@dataclass(frozen=True, eq=False)
class PlanResult:
    """Outcome of a planner: a status, and a path when one was found.

    Attributes
    ----------
    status : Status
        ``EXACT`` (feasible), ``APPROXIMATE`` (best found violates a soft term),
        ``INVALID_START``, ``INVALID_GOAL``, ``INFEASIBLE`` or ``TIMEOUT``.
    path : ndarray, shape (N, 3)
        Dense polyline of the planned path (empty when none).
    cost : float
        Total cost (``inf`` when none).
    cost_terms : dict
        ``length``, ``terrain``, ``energy`` (weighted cost units) and the physical
        ``length_m``, ``energy_j``, ``duration_s``, ``min_clearance_m`` (least geometric
        clearance to the seabed or a static obstacle, margins not subtracted) and ``violations``
        (segments that break a constraint, margins included; ``collisions`` is a deprecated alias).
    evaluations, iterations : int
        Work done.
    wall_time_s : float
        Wall-clock time of the plan.
    history : ndarray
        Best cost after each iteration.
    trace : ndarray, shape (M, 2)
        ``(evaluations, best cost)`` after every batch of objective evaluations (the convergence
        against evaluations, comparable between optimisers).
    planner : str
        Name of the planner.
    control_points : ndarray or None
        B-spline control points ``(K, 3)`` for spline planners.
    message : str
        Human-readable explanation of a failure.
    reference_cost : float
        Cost of the grid reference plan on the same cost function (``nan`` when not computed).
    times : ndarray or None
        Time (s after the mission's start time) at each vertex of ``path``, for timed plans.
    tail : ndarray of bool or None
        ``(N - 1,)`` legs of ``path`` flown tail-first (time-optimal plans with ``tail_first``).
    work : dict
        Work done outside the evaluation budget, by name: the seeded pipeline's lattice seeding
        (``seeding_lattice_nodes``, ``seeding_cpu_s``) and polyline polish (``polish_cpu_s``).
    converged : bool or None
        The seeded pipeline's verdict on its own plan (:mod:`auvplan.planners.swarm.convergence`):
        False when the run's evidence says the plan may not be the best it could reach; None when not
        assessed (other planners and pipelines).
    convergence : str
        The evidence behind ``converged`` (``"<code>: <explanation>"`` when False).
    """

    status: Status
    path: np.ndarray
    cost: float
    cost_terms: dict[str, float]
    evaluations: int
    iterations: int
    wall_time_s: float
    history: FloatArray
    planner: str
    control_points: FloatArray | None = None
    message: str = ""
    reference_cost: float = float("nan")
    trace: FloatArray = field(default_factory=lambda: np.empty((0, 2)))
    times: FloatArray | None = None
    work: dict[str, float] = field(default_factory=dict)
    tail: BoolArray | None = None
    converged: bool | None = None
    convergence: str = ""

    @classmethod
    def failure(cls, status: Status, message: str, planner: str, wall_time_s: float = 0.0) -> PlanResult:
        """A planner's result without a path: its failure status and why, nothing found, no work counted.

        Parameters
        ----------
        status : Status
            The failure (``INVALID_START``, ``INVALID_GOAL``, ``INFEASIBLE`` …).
        message : str
            Why, for the user.
        planner : str
            Name of the planner.
        wall_time_s : float, default 0.0
            Wall-clock time spent before the failure (s).

        Returns
        -------
        PlanResult
            An empty path ``(0, 3)``, ``inf`` cost, no cost terms, no evaluations or iterations, an empty history.
        """
        return cls(status, np.empty((0, 3)), float("inf"), {}, 0, 0, wall_time_s, np.empty(0), planner, None, message)

    @property
    def gap(self) -> float:
        """Cost minus the grid reference's cost.

        Returns
        -------
        float
            ``cost - reference_cost`` (cost units; ``nan`` without a reference).
        """
        return self.cost - self.reference_cost

    @property
    def gap_pct(self) -> float:
        """:attr:`gap` as a percentage of the reference cost.

        Returns
        -------
        float
            Percent (``nan`` without a reference).
        """
        return 100.0 * self.gap / self.reference_cost
