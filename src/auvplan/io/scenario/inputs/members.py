"""``[currents] members``: the current fields of a forecast ensemble (issue 39).

Each member is a table: ``{ file = "model.nc" }`` (a NetCDF current file, or a table with its
variable names as ``[currents] file``; with ``dimension = "realization"`` one member per index of the
file's member dimension), ``{ uniform = [u, v, w] }``, or
``{ perturbation = { count, spread_mps, correlation_m, seed } }`` which stands for ``count`` members
made from the nominal ``[currents]`` field (its ``uniform``, ``vortices``, ``file`` or ``tides``)
plus a smooth random perturbation of the stated spread and correlation length
(:class:`auvplan.world.currents.ensemble.PerturbedCurrent`).  An optional ``name`` labels the member.

The nominal field, the one a plan is made on unless ``[planner] robust`` says otherwise, is the
``[currents]`` field when the table gives one, else the first member.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

from ....errors import DataError
from ....world import CurrentField, UniformCurrent, World
from ....world.currents.ensemble import PerturbedCurrent
from ...data.geo import LocalFrame
from ...data.ocean.currents import CurrentsFileSpec, read_currents
from ...files import limits as _limits

if TYPE_CHECKING:
    from ..specs import Scenario

__all__ = ["PerturbationSpec", "MemberSpec", "member_fields", "scenario_members"]


def _dimension_size(spec: CurrentsFileSpec, dim: str, base_dir: Path | None, where: str) -> int:
    """Length of a file's member dimension (the file is opened, not read)."""
    import xarray as xr  # imported when used (issue 56)

    path = Path(spec.path)
    if not path.is_absolute() and base_dir is not None:
        path = base_dir / path
    try:
        with xr.open_dataset(path, decode_times=False) as ds:
            sizes = dict(ds.sizes)
    except (OSError, ValueError) as exc:
        raise DataError(f"{where} file = {spec.path!r}: cannot read ({exc})") from exc
    if dim not in sizes:
        raise DataError(f"{where} dimension = {dim!r}: not a dimension of {spec.path!r} "
                        f"(it has {', '.join(map(str, sizes)) or 'none'})")
    if not 1 <= sizes[dim] <= 1000:
        raise DataError(f"{where} dimension = {dim!r}: {sizes[dim]} members (1 to 1000 allowed)")
    return int(sizes[dim])


@dataclass(frozen=True)
class PerturbationSpec:
    """Members made by perturbing the nominal field.

    Attributes
    ----------
    count : int
        Number of members, 1 to 1000.
    spread_mps : float
        Standard deviation of each horizontal component of the perturbation (m/s), > 0.
    correlation_m : float
        Correlation length of the perturbation (m), > 0.
    seed : int
        Seed of the first member's field (the next ones take seed + 1, + 2, ...).
    """

    count: int
    spread_mps: float
    correlation_m: float
    seed: int = 0

    def __post_init__(self) -> None:
        if not 1 <= self.count <= 1000:
            raise ValueError(f"count = {self.count}: must lie in [1, 1000]")
        if not self.spread_mps > 0:
            raise ValueError(f"spread_mps = {self.spread_mps}: must be positive")
        if not self.correlation_m > 0:
            raise ValueError(f"correlation_m = {self.correlation_m}: must be positive")
        if self.seed < 0:
            raise ValueError(f"seed = {self.seed}: must be >= 0")


@dataclass(frozen=True)
class MemberSpec:
    """One entry of ``[currents] members``: exactly one of ``file``, ``uniform`` and ``perturbation``.

    Attributes
    ----------
    name : str
        Label of the member (default: ``member<i>`` or the file's name).
    file : str or CurrentsFileSpec or None
        A NetCDF current file.
    uniform : tuple of 3 float or None
        A uniform current (m/s; east, north, up).
    perturbation : PerturbationSpec or None
        Perturbed copies of the nominal field.
    dimension : str
        With ``file``: the file's member/realisation dimension; the entry stands for one member per index.
    """

    name: str = ""
    file: str | CurrentsFileSpec | None = None
    uniform: tuple[float, float, float] | None = None
    perturbation: PerturbationSpec | None = None
    dimension: str = ""

    def __post_init__(self) -> None:
        if isinstance(self.file, str):
            object.__setattr__(self, "file", CurrentsFileSpec(path=self.file))
        kinds = [k for k in ("file", "uniform", "perturbation") if getattr(self, k) is not None]
        if len(kinds) != 1:
            raise ValueError("give exactly one of 'file', 'uniform' and 'perturbation' "
                             f"(got {', '.join(kinds) or 'none'})")
        if self.dimension and self.file is None:
            raise ValueError(f"dimension = {self.dimension!r}: a member dimension needs a 'file'")
        if len(self.name) > 64 or any(not c.isprintable() or c in "@~," for c in self.name):
            # a name of '@' or '~' was cut apart by bench's scenario@member~seed labels, a control character split
            # the one-line messages naming the member (hostile round 20)
            raise ValueError(f"name = {self.name[:80]!r}: a member's name is 1-64 characters without '@', '~', ',' "
                             "or control and formatting characters (it labels rows and messages)")

    @property
    def count(self) -> int:
        """How many members this entry stands for."""
        return self.perturbation.count if self.perturbation is not None else 1


def member_fields(members: tuple[MemberSpec, ...], nominal: CurrentField, frame: LocalFrame | None,
                  box: tuple[float, float, float, float], *, source: str, base_dir: Path | None = None,
                  start_time: str = "", first_only: bool = False) -> tuple[tuple[str, CurrentField], ...]:
    """Read or make every member's current field, each checked to cover the bounds.

    Parameters
    ----------
    members : tuple of MemberSpec
        The ``[currents] members`` entries.
    nominal : CurrentField
        The ``[currents]`` field that perturbation members perturb.
    frame : LocalFrame or None
        The scenario's local frame (for geographic files).
    box : (xmin, xmax, ymin, ymax)
        The world's horizontal bounds (m).
    source : str
        The scenario file, for messages.
    base_dir : pathlib.Path, optional
        Folder that relative paths resolve against.
    start_time : str
        ``[mission] start_time`` (ISO 8601) matched to each file's time axis.
    first_only : bool
        Make the first member only.

    Returns
    -------
    tuple of (str, CurrentField)
        Name and field of each member, in order (perturbation entries expanded).

    Raises
    ------
    DataError
        Naming the scenario, ``[currents] members[i]``, the key and the value when a member
        cannot be read or does not cover the bounds.
    """
    out: list[tuple[str, CurrentField]] = []
    sizes = [_dimension_size(m.file, m.dimension, base_dir, f"{source}: [currents] members[{i}]")  # type: ignore[arg-type]
             if m.file is not None and m.dimension else m.count for i, m in enumerate(members)]
    _limits.check_members(f"{source}: [currents] members", sizes)  # in total, before any member is read
    for i, m in enumerate(members):
        where = f"{source}: [currents] members[{i}]"
        if m.file is not None:
            out += _file_members(m, sizes[i], where, frame, box, base_dir, start_time, first_only)
        elif m.uniform is not None:
            out.append((m.name or f"member{len(out)}", UniformCurrent(m.uniform)))
        else:
            p = m.perturbation
            assert p is not None
            for j in range(p.count):
                out.append((f"{m.name or 'perturbed'}{j}",
                            PerturbedCurrent(nominal, p.spread_mps, p.correlation_m, p.seed + j)))
        if first_only and out:
            return tuple(out[:1])
    return tuple(out)



def _file_members(m: MemberSpec, size: int, where: str, frame: LocalFrame | None,
                  box: tuple[float, float, float, float], base_dir: Path | None, start_time: str,
                  first_only: bool) -> list[tuple[str, CurrentField]]:
    """A file member's field, or one per index of its ``dimension`` (``size``), each checked to cover the bounds
    (the first only, with ``first_only``)."""
    spec = m.file
    assert isinstance(spec, CurrentsFileSpec)
    label = m.name or Path(spec.path).stem
    picks: list[tuple[str, int] | None] = [None]
    if m.dimension:
        picks = [(m.dimension, j) for j in range(size)]
    out: list[tuple[str, CurrentField]] = []
    for pick in picks:
        try:
            field: CurrentField = read_currents(spec, frame, base_dir=base_dir, extent_m=box,
                                                start_time=start_time, member=pick)
        except DataError as exc:
            raise DataError(f"{where} file = {spec.path!r}: {exc}") from exc
        if not field.covers(*box):
            raise DataError(f"{where} file = {spec.path!r}: does not cover the bounds x [{box[0]:.0f}, "
                            f"{box[1]:.0f}] y [{box[2]:.0f}, {box[3]:.0f}] m")
        out.append((label if pick is None else f"{label}[{pick[1]}]", field))
        if first_only:
            break
    return out

def scenario_members(sc: Scenario, world: World, seed: int | None = None) -> tuple[tuple[str, CurrentField], ...]:
    """The scenario's members, its perturbation entries re-drawn with ``seed`` when given.

    Parameters
    ----------
    sc : Scenario
        The scenario (its ``[currents] members``).
    world : World
        Its world (bounds and the nominal field the perturbations perturb).
    seed : int, optional
        Seed in place of every ``perturbation`` entry's.

    Returns
    -------
    tuple of (str, CurrentField)
        Name and field of each member (empty without members).
    """
    members = sc.currents.members
    if not members:
        return ()
    if seed is not None:
        members = tuple(replace(m, perturbation=replace(m.perturbation, seed=seed)) if m.perturbation else m
                        for m in members)
    b = world.bounds
    frame = LocalFrame(sc.origin.lat, sc.origin.lon) if sc.origin else None
    return member_fields(members, world.currents, frame, (b.xmin, b.xmax, b.ymin, b.ymax), source=sc.source,
                         base_dir=sc.base_dir, start_time=sc.mission.start_time)
