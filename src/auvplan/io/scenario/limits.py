"""Resource budget of a scenario (the ``[limits]`` table), checked before anything is allocated.

Every size a scenario controls is turned into an estimate of the memory it will take, and an
estimate over the budget is a :class:`ScenarioError` that names the keys, the sizes, the estimate
and the limit, and says which key raises it — instead of a ``MemoryError`` (or a swapping
machine) minutes later.  The per-item byte counts are measured peaks (``tracemalloc``, see
``tests/test_limits.py``) rounded up:

* terrain grid (file resampling, synthetic): ~160 B per node (axes, elevation, interpolation
  coefficients, regrid temporaries);
* swarm population × samples: ~200 B per sample point (population arrays, cost temporaries);
* random-walk obstacle track: ~100 B per step (``duration / dt``);
* simulation record: ~(96 + 8 × obstacles) B per recorded step;
* lattice reference planner: ~1.3 kB per node (edges, costs, Dijkstra heap).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ...errors import ScenarioError

__all__ = [
    "Limits",
    "BYTES_PER_TERRAIN_NODE",
    "BYTES_PER_SAMPLE",
    "BYTES_PER_WALK_STEP",
    "BYTES_PER_LATTICE_NODE",
    "check",
    "grid_nodes",
    "sim_bytes",
]

BYTES_PER_TERRAIN_NODE = 160
BYTES_PER_SAMPLE = 200
BYTES_PER_WALK_STEP = 100
BYTES_PER_LATTICE_NODE = 1300
_MIB = 1024.0 * 1024.0


@dataclass(frozen=True)
class Limits:
    """Resource budget (``[limits]``).

    Attributes
    ----------
    memory_mb : float
        Largest estimated memory (MiB) of any one structure a scenario asks for: the terrain
        grid, a swarm population's samples, a random-walk track, the simulation record, the
        reference lattice.  Raise it on a machine with more memory.
    """

    memory_mb: float = 2048.0

    def __post_init__(self) -> None:
        if not self.memory_mb > 0:
            raise ValueError(f"memory_mb = {self.memory_mb}: must be positive")


def check(limits: Limits, where: str, what: str, nbytes: float) -> None:
    """Raise a :class:`ScenarioError` when ``nbytes`` exceeds the budget.

    Parameters
    ----------
    limits : Limits
        The scenario's budget.
    where : str
        Message prefix naming the file and table, e.g. ``"s.toml: [planner]"``.
    what : str
        The keys and sizes behind the estimate, e.g. ``"population × samples = 10 × 10^9"``.
    nbytes : float
        Estimated bytes (may be inf or nan: treated as over any budget).
    """
    if nbytes <= limits.memory_mb * _MIB:  # nan compares False: refused
        return
    mib = nbytes / _MIB
    shown = ("unbounded memory" if not math.isfinite(mib) else f"{mib:,.0f} MiB" if mib < 1e9 else f"{mib:.3g} MiB")
    raise ScenarioError(f"{where} {what} needs ~{shown}, over the limit of {limits.memory_mb:g} MiB; "
                        f"make it smaller, or raise [limits] memory_mb")


def grid_nodes(span_x: float, span_y: float, cell: float) -> float:
    """Count the nodes of a regular grid of ``cell`` over ``span_x × span_y`` (as the resamplers count them).

    Parameters
    ----------
    span_x, span_y : float
        Extent of the grid (m).
    cell : float
        Grid spacing (m).

    Returns
    -------
    float
        Number of nodes (a float: may be huge or inf for a tiny cell).
    """
    if not cell > 0:
        return math.inf
    return (math.floor(span_x / cell + 0.5) + 1.0) * (math.floor(span_y / cell + 0.5) + 1.0)


def sim_bytes(length_m: float, speed: float, max_time: float, dt: float, record_every: int, n_obstacles: int) -> float:
    """Estimate the memory of the closed-loop simulation's record (preallocated for the time limit).

    Parameters
    ----------
    length_m : float
        Route length (m).
    speed : float
        Cruise speed (m/s).
    max_time : float
        Time limit (s); 0 = 3 × nominal + 120 s.
    dt : float
        Time step (s).
    record_every : int
        Record every this many steps.
    n_obstacles : int
        Static and moving obstacles (one distance column each).

    Returns
    -------
    float
        Bytes.
    """
    t = max_time or 3.0 * length_m / speed + 120.0
    steps = t / dt / record_every + 2.0
    return steps * (96.0 + 8.0 * n_obstacles)
