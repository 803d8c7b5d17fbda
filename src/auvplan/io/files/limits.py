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
* lattice reference planner: ~48 B per node plus 24 MiB (:func:`lattice_bytes`; node fields by
  slabs, one bit per edge and direction, the compiled search's arrays; measured by ``tracemalloc``
  on marcus-wake at 1 000, 500 and 250 m: peak = 41.6 B per node + 13 MB, so the estimate is
  1.2–1.7× the measured peak from 10⁵ nodes up, within 2× in ``tests/unit/test_lattice.py``);
* a data variable read from a file (NetCDF, GeoTIFF): ~24 B per declared cell (float64 values,
  the masked/filled copy, flips; measured 15 B, 21 B with a flipped axis), from the file's header
  — *before* a byte of it is read, so a 5 MB sparse file that declares 400 000 × 400 000 cells is
  refused naming the file, the variable and its shape;
* the time-optimal planner (``[planner.timeopt]``): ~900 B per lattice node (positions, clearances,
  the 50 leg flags, the search's arrays) and ~44 B per node and time step of its current table
  (sampled as float64, kept as float32), ``horizon_s / dt`` steps (measured on juan-de-fuca-tides,
  31 236 and 62 472 nodes × 97 and 383 steps: 840 B and 40 B), and the front method's stored fronts,
  8 B per horizontal node and step of a cell at ``V + 1.5 V`` over the horizon;
* a results folder's ``run.npz``: each member's declared shape × item size (its header) and its
  uncompressed size (the archive's directory), whichever is larger;
* a formation's slot tracks (``[formation] sample_m``): ~400 B per vehicle and sample (tracks,
  segments, the exact segment test; measured 284 B on chagos-formation at 10 m and 5 m).

The scenario's budget is set for the readers by :func:`budget` (a context: the data readers take
no ``limits`` argument); outside one, :data:`DEFAULT` applies (``data inspect``, ``report``).
"""

from __future__ import annotations

import contextlib
import math
import zipfile
from collections.abc import Iterator, Sequence
from contextvars import ContextVar
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from ...errors import DataError, ScenarioError

__all__ = [
    "Limits",
    "BYTES_PER_TERRAIN_NODE",
    "BYTES_PER_FRONT_SAMPLE",
    "BYTES_PER_SAMPLE",
    "BYTES_PER_WALK_STEP",
    "BYTES_PER_LATTICE_NODE",
    "LATTICE_FIXED_BYTES",
    "lattice_bytes",
    "BYTES_PER_DATA_CELL",
    "BYTES_PER_TIMEOPT_NODE",
    "BYTES_PER_TABLE_SAMPLE",
    "BYTES_PER_TRACK_SAMPLE",
    "DEFAULT",
    "BudgetError",
    "budget",
    "current",
    "check",
    "check_declared",
    "check_npz",
    "grid_nodes",
    "sim_bytes",
    "timeopt_size",
    "BYTES_PER_ENDURANCE_STEP",
    "MAX_ENDURANCE_STEPS",
    "check_endurance",
    "check_route_endurance",
    "MAX_ENSEMBLE_MEMBERS",
    "check_members",
    "BYTES_PER_SURVEY_STATION",
    "MAX_SURVEY_LINES",
    "check_survey",
    "MAX_PLAN_SAMPLES",
    "check_plan_work",
]

BYTES_PER_TERRAIN_NODE = 160
#: The front method's stored level-set function: float32 per horizontal node and step, and its stacked copy.
BYTES_PER_FRONT_SAMPLE = 8
BYTES_PER_SAMPLE = 200
BYTES_PER_WALK_STEP = 100
BYTES_PER_LATTICE_NODE = 48
LATTICE_FIXED_BYTES = 24 * 1024 * 1024
BYTES_PER_DATA_CELL = 24
BYTES_PER_TIMEOPT_NODE = 900
BYTES_PER_TABLE_SAMPLE = 44
BYTES_PER_TRACK_SAMPLE = 400
BYTES_PER_ENDURANCE_STEP = 400
MAX_ENDURANCE_STEPS = 2_000_000
MAX_ENSEMBLE_MEMBERS = 1000
BYTES_PER_SURVEY_STATION = 200
MAX_SURVEY_LINES = 5000
MAX_PLAN_SAMPLES = 2e9
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


class BudgetError(DataError):
    """A data file declares more than the memory budget (names the file, the shape, the size, the limit)."""


DEFAULT = Limits()
"""The budget outside a scenario (``data inspect``, reading a results folder)."""

_ACTIVE: ContextVar[Limits] = ContextVar("auvplan_limits", default=DEFAULT)


@contextlib.contextmanager
def budget(limits: Limits) -> Iterator[Limits]:
    """Make ``limits`` the budget of the data readers inside the ``with`` block.

    Parameters
    ----------
    limits : Limits
        The scenario's ``[limits]``.

    Yields
    ------
    Limits
        ``limits``.
    """
    token = _ACTIVE.set(limits)
    try:
        yield limits
    finally:
        _ACTIVE.reset(token)


def current() -> Limits:
    """The budget in force (:func:`budget`, else :data:`DEFAULT`).

    Returns
    -------
    Limits
        The budget.
    """
    return _ACTIVE.get()


def check(limits: Limits, where: str, what: str, nbytes: float, *, error: type[Exception] = ScenarioError,
          hint: str = "make it smaller, or raise [limits] memory_mb") -> None:
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
    error : type, optional
        The exception raised (:class:`DataError` for a data file).
    hint : str, optional
        What the user can do, ending the message.
    """
    if nbytes <= limits.memory_mb * _MIB:  # nan compares False: refused
        return
    mib = nbytes / _MIB
    shown = ("unbounded memory" if not math.isfinite(mib) else f"{mib:.3g} MiB" if mib < 10 or mib >= 1e9
             else f"{mib:,.0f} MiB")
    raise error(f"{where} {what} needs ~{shown}, over the limit of {limits.memory_mb:g} MiB; {hint}")


def check_declared(where: str, what: str, shape: Sequence[int], per_cell: float = BYTES_PER_DATA_CELL) -> None:
    """Refuse to read a variable whose declared shape is over the budget in force (a :class:`DataError`).

    Parameters
    ----------
    where : str
        The file (and variable), e.g. ``"grid.nc: variable 'z'"``.
    what : str
        What the shape is, e.g. ``"declares"``.
    shape : sequence of int
        The declared shape (from the header: nothing has been read).
    per_cell : float, optional
        Bytes per cell once read.
    """
    cells = math.prod(float(n) for n in shape)
    dims = " × ".join(f"{int(n):,}" for n in shape) or "a scalar"
    check(current(), where, f"{what} {dims} = {cells:.3g} cells, which", cells * per_cell, error=BudgetError,
          hint="crop or decimate the file, or raise [limits] memory_mb")


def check_npz(path: Path, limits: Limits | None = None) -> None:
    """Refuse an ``.npz`` archive whose members declare more than the budget (headers only are read).

    Each member's ``.npy`` header gives its shape and dtype; the archive's directory gives its
    uncompressed size (a compression bomb declares a small shape but a huge member).

    Parameters
    ----------
    path : pathlib.Path
        The archive.
    limits : Limits, optional
        The budget; default the one in force.

    Raises
    ------
    DataError
        Naming the file, the member, its declared shape and size, and the limit.
    """
    limits = limits or current()
    total = 0.0
    for name, shape, dtype, size in _npz_headers(path):
        nbytes = max(math.prod(float(n) for n in shape) * dtype.itemsize, float(size))
        total += nbytes
        check(limits, f"{path}: member {name!r}", f"declares shape {tuple(shape)} {dtype} "
              f"({size:,} bytes uncompressed), which", nbytes, error=BudgetError,
              hint="the file is damaged or not auvplan's")
    check(limits, f"{path}:", "its members together", total, error=BudgetError,
          hint="the file is damaged or not auvplan's")


def _npz_headers(path: Path) -> list[tuple[str, tuple[int, ...], np.dtype[np.generic], int]]:
    """``(member, declared shape, dtype, uncompressed bytes)`` of each member of an ``.npz`` (headers only)."""
    out = []
    try:
        with zipfile.ZipFile(path) as zf:
            for info in zf.infolist():
                with zf.open(info) as fh:
                    version = np.lib.format.read_magic(fh)
                    shape, _, dtype = (np.lib.format.read_array_header_1_0(fh) if version == (1, 0)
                                       else np.lib.format.read_array_header_2_0(fh))
                out.append((info.filename.removesuffix(".npy"), tuple(shape), dtype, info.file_size))
    except (zipfile.BadZipFile, ValueError, OSError, EOFError) as exc:
        raise DataError(f"{path}: not a readable .npz archive ({' '.join(str(exc).split())[:160]})") from exc
    return out


def timeopt_size(span_x: float, span_y: float, cell: float, levels: int, horizon_s: float,
                 dt: float, front_speed: float = 0.0) -> tuple[float, float, float]:
    """Estimate the time-optimal planner's lattice and current table (as ``timeplan.setup`` builds them).

    Parameters
    ----------
    span_x, span_y : float
        Horizontal sides of the search box (m).
    cell : float
        Lattice cell (m); 0 = 1/100 of the larger side.
    levels : int
        Depth levels.
    horizon_s : float
        Time the table covers (s).
    dt : float
        Table time step (s).
    front_speed : float, default 0
        The front method's ``V + max |c|`` (m/s; 0: no front): it keeps its level-set function,
        float32, at every horizontal node for every step of a cell at that speed over the horizon
        (:data:`BYTES_PER_FRONT_SAMPLE` with the copy that stacks them).

    Returns
    -------
    nodes, steps, nbytes : float
        Lattice nodes, table time steps and estimated bytes.
    """
    cell = cell or max(span_x, span_y) / 100.0
    if not cell > 0 or not dt > 0:
        return math.inf, math.inf, math.inf
    nodes = (_floor(span_x / cell + 1e-9) + 1.0) * (_floor(span_y / cell + 1e-9) + 1.0) * max(levels, 1)
    steps = max(-_floor(-horizon_s / dt), 1.0) + 1.0
    front = nodes / max(levels, 1) * (horizon_s * front_speed / cell + 2.0) * BYTES_PER_FRONT_SAMPLE \
        if front_speed else 0.0
    return nodes, steps, nodes * (BYTES_PER_TIMEOPT_NODE + steps * BYTES_PER_TABLE_SAMPLE) + front


def lattice_bytes(nodes: float) -> float:
    """Estimate the peak memory of the lattice reference planner building and searching a lattice.

    Parameters
    ----------
    nodes : float
        Lattice nodes.

    Returns
    -------
    float
        Bytes: :data:`BYTES_PER_LATTICE_NODE` a node plus :data:`LATTICE_FIXED_BYTES` (the node
        fields' slab temporaries, the per-column seabed and land).
    """
    return float(nodes) * BYTES_PER_LATTICE_NODE + LATTICE_FIXED_BYTES


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
    return (_floor(span_x / cell + 0.5) + 1.0) * (_floor(span_y / cell + 0.5) + 1.0)


def _floor(v: float) -> float:
    """``math.floor`` that keeps inf and nan (a tiny cell over a wide span) instead of raising."""
    return float(math.floor(v)) if math.isfinite(v) else v


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


def check_endurance(limits: Limits, where: str, length_m: float, legs: int, ds_m: float) -> None:
    """Refuse an energy integration of more steps than :data:`MAX_ENDURANCE_STEPS` or over the budget.

    The energy budget flies each leg in ``ds_m`` sub-steps (two current evaluations and one stored node
    each: ~:data:`BYTES_PER_ENDURANCE_STEP` and a step of Python work); ``length / ds_m + legs`` steps.

    Parameters
    ----------
    limits : Limits
        The budget.
    where : str
        The file and table (``s.toml: [endurance]``) or what is checked.
    length_m : float
        Length of the mission (m).
    legs : int
        Its legs.
    ds_m : float
        ``[endurance] ds_m`` (m).
    """
    steps = length_m / ds_m + legs if ds_m > 0 else math.inf
    what = f"ds_m = {ds_m:g} m over a {length_m:.4g} m mission of {legs} legs ({steps:.3g} integration steps)"
    if not steps <= MAX_ENDURANCE_STEPS:  # nan and inf too
        raise ScenarioError(f"{where} {what}: over the {MAX_ENDURANCE_STEPS:,} steps allowed; raise ds_m, or "
                            "shorten the mission (every position lies in the scenario's area)")
    check(limits, where, what + ", which", steps * BYTES_PER_ENDURANCE_STEP)


def check_route_endurance(where: str, waypoints: ArrayLike, ds_m: float) -> None:
    """Refuse the energy integration of a route at ``ds_m`` beyond the budget in force (:func:`check_endurance`).

    Parameters
    ----------
    where : str
        What is checked, for the message (``s.toml: [endurance]``, ``serve: the mission``).
    waypoints : array_like
        ``(N, 3)`` the route (m); fewer than two points count as one leg of no length.
    ds_m : float
        ``[endurance] ds_m`` (m).
    """
    w = np.asarray(waypoints, dtype=float).reshape(-1, 3)
    length = float(np.linalg.norm(np.diff(w, axis=0), axis=1).sum()) if w.shape[0] > 1 else 0.0
    check_endurance(current(), where, length, max(w.shape[0] - 1, 1), ds_m)


def check_members(where: str, counts: Sequence[int]) -> None:
    """Refuse an ensemble of more than :data:`MAX_ENSEMBLE_MEMBERS` members in total over its entries.

    Parameters
    ----------
    where : str
        ``s.toml: [currents] members``.
    counts : sequence of int
        Members each entry stands for.
    """
    total = sum(int(c) for c in counts)
    if total > MAX_ENSEMBLE_MEMBERS:
        raise ScenarioError(f"{where}: {len(counts)} entries stand for {total:,} members in total; at most "
                            f"{MAX_ENSEMBLE_MEMBERS:,} (every plan is scored on every member)")


def check_survey(limits: Limits, where: str, span_m: float, length_m: float, spacing_m: float,
                 station_m: float, step_m: float, swath_m: float) -> None:
    """Refuse a survey whose lines, stations or swath samples are over the ceilings (before any is planned).

    Parameters
    ----------
    limits : Limits
        The budget.
    where : str
        ``s.toml: [survey]``.
    span_m : float
        Width of the area across the lines (its largest side: the lines may take any heading) (m).
    length_m : float
        Length of the area along the lines (m).
    spacing_m : float
        The least line spacing the sensor allows over the area (swath × (1 − the largest overlap)) (m).
    station_m, step_m : float
        Station spacing along the lines and the seabed sampling step under the swath (m).
    swath_m : float
        The widest swath over the area (m).
    """
    lines = span_m / spacing_m + 1.0 if spacing_m > 0 else math.inf
    what = (f"the area ({span_m:.4g} × {length_m:.4g} m) at a line spacing of ~{spacing_m:.3g} m "
            f"({lines:.3g} lines)")
    if not lines <= MAX_SURVEY_LINES:
        raise ScenarioError(f"{where} {what}: over the {MAX_SURVEY_LINES:,} lines allowed; a smaller area, a "
                            "wider swath (opening_deg, range_m, altitude_m) or less overlap")
    stations = lines * (length_m / station_m + 1.0) if station_m > 0 else math.inf
    samples = stations * (swath_m / step_m + 1.0) if step_m > 0 else math.inf
    check(limits, where, f"{what}, station_m = {station_m:g} m, step_m = {step_m:g} m ({stations:.3g} stations, "
          f"{samples:.3g} swath samples), which", stations * BYTES_PER_SURVEY_STATION + samples * 8.0 * 3)


def check_plan_work(where: str, population: int, iterations: int, budget: int, samples: int) -> None:
    """Refuse a swarm plan of more than :data:`MAX_PLAN_SAMPLES` path samples costed (time, not memory).

    Parameters
    ----------
    where : str
        ``s.toml: [planner]``.
    population, iterations, budget, samples : int
        The ``[planner]`` keys (``budget = 0``: ``population × iterations`` evaluations).
    """
    evaluations = float(budget) if budget > 0 else float(population) * float(iterations)
    work = evaluations * float(samples)
    if work > MAX_PLAN_SAMPLES:
        what = (f"budget = {budget}" if budget > 0 else f"population × iterations = {population} × {iterations}")
        raise ScenarioError(f"{where} {what} evaluations × samples = {samples}: {work:.3g} path samples to cost, "
                            f"over the {MAX_PLAN_SAMPLES:.0e} allowed (hours of work); lower iterations or budget")
