"""The planner registry: the one plug-in point of the global planners (after OMPL's planner factory
and robotics-toolbox's planner classes).

A planner is a function ``run(problem, spec, rng, progress) -> PlanResult``: the
:class:`~auvplan.planners.base.PlanningProblem` (world, end points, vehicle figures) as one
object, the :class:`~auvplan.planners.base.PlannerSpec` (its settings), a seed or generator and
an optional ``progress(iteration, best_cost)``.  A deterministic planner that neither draws nor
iterates registers its ``plan(problem, spec)`` (or ``plan(problem, settings)``) with ``deterministic`` set,
and the registry calls it under that signature (:func:`deterministic_run`).  :func:`register` adds one
under a name, with the frozen dataclass of its settings; from then on

- :class:`~auvplan.planners.base.PlannerSpec` accepts the name (``[planner] name = "..."``),
- a scenario's ``[planner.<name>]`` table is read into the settings type, and the planner gets it back
  with ``spec.params_for()``,
- ``auvplan plan --planner <name>`` and :func:`auvplan.planners.plan` run it.

The planner names, their settings types and whether they iterate all come from here.  The built-in
planners are registered by the dotted path of their function, imported the first time one runs, so
naming or checking a planner imports none.  A planner from another package registers itself when its
module is imported, or through the entry-point group ``auvplan.planners`` (each entry point names a
module or object; the group is loaded the first time an unknown name is asked for)::

    [project.entry-points."auvplan.planners"]
    straight = "my_package.straight"
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass
from importlib import metadata
from typing import Any, Literal

__all__ = ["PlannerEntry", "REGISTRY", "register", "get", "names", "known", "load_plugins", "ENTRY_POINTS",
           "PLANNERS", "SWARM", "PIPELINES", "Deterministic", "deterministic_run"]

PlannerFn = Callable[..., Any]
"""``run(problem, spec, rng, progress) -> PlanResult``."""

Deterministic = Literal["spec", "settings"]
"""What a deterministic planner's ``plan`` takes besides the problem: the whole
:class:`~auvplan.planners.base.PlannerSpec` (``"spec"``) or only its own settings (``"settings"``,
``spec.params_for(name)``)."""

ENTRY_POINTS = "auvplan.planners"
"""The entry-point group that other packages register planners in."""

PLANNERS = ("iabc", "abc", "ga", "pso", "de", "flow", "grid", "timeopt")
"""The built-in planner names: the four swarm optimisers (document 002), scipy's differential
evolution, the streamline planner (document 000), the lattice reference planner and the time-optimal
planner in tidal currents (:func:`names` adds the registered ones)."""
SWARM = ("iabc", "abc", "ga", "pso", "de")
"""The population optimisers over B-spline control points (they iterate and call
``progress(iteration, best)``)."""
PIPELINES = ("seeded", "document", "progressive")
"""The swarm planners' pipelines (``[planner] pipeline``)."""


def deterministic_run(plan: PlannerFn, takes: Deterministic, name: str) -> PlannerFn:
    """A deterministic ``plan`` under the registry's signature ``run(problem, spec, rng, progress)``.

    Parameters
    ----------
    plan : callable
        ``plan(problem, spec) -> PlanResult`` or ``plan(problem, settings) -> PlanResult``.
    takes : {"spec", "settings"}
        Which of the two ``plan`` is.
    name : str
        The planner's registered name (whose settings ``"settings"`` passes).

    Returns
    -------
    callable
        ``run(problem, spec, rng=None, progress=None)``: ``rng`` and ``progress`` unused (the planner
        draws nothing and does not iterate).
    """
    if takes not in ("spec", "settings"):
        raise ValueError(f"planner {name!r}: deterministic = {takes!r}; choose 'spec' or 'settings'")

    def run(problem: Any, spec: Any, rng: Any = None, progress: Any = None) -> Any:
        return plan(problem, spec if takes == "spec" else spec.params_for(name))

    run.__name__ = run.__qualname__ = f"run_{name}"
    run.__doc__ = f":func:`{getattr(plan, '__qualname__', plan)}` of planner {name!r} under the registry's signature."
    return run


def _resolve(target: Any) -> Any:
    """An object, or the object a ``"module:name"`` path names (imported now)."""
    if not isinstance(target, str):
        return target
    module, _, name = target.partition(":")
    return getattr(importlib.import_module(module), name)


@dataclass(frozen=True)
class PlannerEntry:
    """A registered planner: its function, whether it iterates, a description and its settings type.

    Parameters
    ----------
    name : str
        Registered name (``spec.name``).
    target : callable or str
        ``run(problem, spec, rng, progress) -> PlanResult``, or the ``"module:function"`` path of one
        (imported when first run).
    iterative : bool
        Whether it iterates and calls ``progress``.
    description : str
        One line for the command line and the docs.
    params : type or str or None
        Its settings: a frozen dataclass (or its ``"module:Class"`` path); None for none.
    table : str or None
        Where :class:`~auvplan.planners.base.PlannerSpec` keeps those settings: the attribute of a
        built-in planner (``"flow"``, ``"iabc"`` …); None for a planner registered from outside,
        whose ``[planner.<name>]`` table :meth:`PlannerSpec.params_for` returns.
    deterministic : {"spec", "settings"} or None
        None: ``target`` is ``run(problem, spec, rng, progress)``.  Otherwise ``target`` is a deterministic
        ``plan(problem, spec)`` (``"spec"``) or ``plan(problem, settings)`` (``"settings"``), which
        :attr:`run` calls under the registry's signature (:func:`deterministic_run`).
    zones : bool, default False
        Whether the planner keeps out of a world's charted no-go zones (``[[zones]]``); one that does
        not is refused when the world has any (:func:`auvplan.planners.plan`).
    """

    name: str
    target: PlannerFn | str
    iterative: bool
    description: str
    params: type | str | None = None
    table: str | None = None
    deterministic: Deterministic | None = None
    zones: bool = False

    @property
    def run(self) -> PlannerFn:
        """The planner function (imported on first use).

        Returns
        -------
        callable
            ``run(problem, spec, rng, progress) -> PlanResult``.
        """
        fn: PlannerFn = _resolve(self.target)
        return fn if self.deterministic is None else deterministic_run(fn, self.deterministic, self.name)

    @property
    def settings_type(self) -> type | None:
        """The planner's settings dataclass (imported on first use).

        Returns
        -------
        type or None
            The frozen dataclass of its settings, None when it takes none.
        """
        cls: type | None = _resolve(self.params)
        return cls


REGISTRY: dict[str, PlannerEntry] = {}
_PLUGINS_LOADED = False


def _add(entry: PlannerEntry) -> None:
    if not entry.name.isidentifier():
        raise ValueError(f"planner name {entry.name!r} must be an identifier (letters, digits, _)")
    if entry.deterministic not in (None, "spec", "settings"):
        raise ValueError(f"planner {entry.name!r}: deterministic = {entry.deterministic!r}; choose 'spec' or "
                         "'settings'")
    if entry.deterministic is not None and entry.iterative:
        raise ValueError(f"planner {entry.name!r}: a deterministic plan function does not iterate")
    if entry.name in REGISTRY:
        raise ValueError(f"planner {entry.name!r} is already registered")
    REGISTRY[entry.name] = entry


def register(name: str, *, iterative: bool, description: str, params: type | None = None,
             deterministic: Deterministic | None = None, zones: bool = False) -> Callable[[PlannerFn], PlannerFn]:
    """Decorator: register ``run(problem, spec, rng, progress)`` as planner ``name`` (or, with
    ``deterministic``, a ``plan(problem, spec)`` or ``plan(problem, settings)``).

    Parameters
    ----------
    name : str
        Planner name (new, an identifier): ``[planner] name`` and ``--planner`` accept it.
    iterative : bool
        Whether the planner iterates and calls ``progress``.
    description : str
        One line describing it.
    params : type, optional
        A frozen dataclass of its settings: a scenario's ``[planner.<name>]`` table is read into it
        (unknown keys and bad values rejected with the file, key and value), and the planner gets it
        from ``spec.params_for()`` (its defaults when the table is absent).
    deterministic : {"spec", "settings"}, optional
        The decorated function is a deterministic ``plan(problem, spec)`` (``"spec"``) or
        ``plan(problem, settings)`` (``"settings"``): no generator, no progress (``iterative`` False).
    zones : bool, default False
        The planner keeps out of ``[[zones]]`` (else it is refused in a world that has any).

    Returns
    -------
    callable
        The decorator; it returns the function unchanged.

    Raises
    ------
    ValueError
        If ``name`` is already registered or is not an identifier, or ``deterministic`` is not one of the
        two forms or comes with ``iterative`` (when the decorator is applied).
    """

    def add(run: PlannerFn) -> PlannerFn:
        _add(PlannerEntry(name, run, iterative, description, params, None, deterministic, zones))
        return run

    return add


def load_plugins() -> None:
    """Load the planners other packages declare in the entry-point group ``auvplan.planners`` (once)."""
    global _PLUGINS_LOADED
    if _PLUGINS_LOADED:
        return
    _PLUGINS_LOADED = True
    for ep in metadata.entry_points(group=ENTRY_POINTS):
        ep.load()  # importing the module registers its planners


def known(name: str) -> bool:
    """Whether a planner is registered under ``name`` (the entry points loaded if needed).

    Parameters
    ----------
    name : str
        Planner name.

    Returns
    -------
    bool
        True when :func:`get` finds it.
    """
    if name not in REGISTRY:
        load_plugins()
    return name in REGISTRY


def names() -> tuple[str, ...]:
    """Every registered planner name, the built-in ones first.

    Returns
    -------
    tuple of str
        The names ``[planner] name`` and ``--planner`` accept.
    """
    load_plugins()
    return tuple(REGISTRY)


def get(name: str) -> PlannerEntry:
    """The planner registered as ``name``.

    Parameters
    ----------
    name : str
        Planner name.

    Returns
    -------
    PlannerEntry
        Its registry entry.

    Raises
    ------
    ValueError
        If no planner has that name.
    """
    if not known(name):
        raise ValueError(f"unknown planner {name!r}; choose one of {', '.join(REGISTRY)}")
    return REGISTRY[name]


_SWARM_TEXT = {
    "iabc": ("improved artificial bee colony over B-splines (document 002)", "auvplan.optim.bee:IABCParams"),
    "abc": ("artificial bee colony (Karaboga 2005) over B-splines", "auvplan.optim.bee:ABCParams"),
    "ga": ("real-coded genetic algorithm (SBX, polynomial mutation) over B-splines", "auvplan.optim.ga:GAParams"),
    "pso": ("particle swarm (Clerc-Kennedy constants) over B-splines", "auvplan.optim.pso:PSOParams"),
    "de": ("scipy's differential evolution (vectorised) over B-splines", "auvplan.optim.de:DEParams"),
}
for _name, (_text, _params) in _SWARM_TEXT.items():
    _add(PlannerEntry(_name, "auvplan.planners.swarm.planner:plan_swarm", True, _text, _params, _name, zones=True))
# the deterministic planners: their plan functions, called under the registry's signature
_add(PlannerEntry("flow", "auvplan.planners.flow.planner:plan_flow", False,
                  "potential-flow streamline from the start (document 000)", "auvplan.planners.params:FlowParams",
                  "flow", deterministic="settings"))
_add(PlannerEntry("grid", "auvplan.planners.grid.planner:plan_grid", False,
                  "lattice reference: Dijkstra cost-to-go, elastic band, B-spline",
                  "auvplan.planners.params:GridParams", "grid", deterministic="spec", zones=True))
_add(PlannerEntry("timeopt", "auvplan.planners.timeopt.planner:plan_timeopt", False,
                  "time-optimal path in tidal currents, departure time given", "auvplan.planners.params:TimeoptParams",
                  "timeopt", deterministic="spec", zones=True))

if tuple(REGISTRY) != PLANNERS:  # pragma: no cover - a programming error
    raise RuntimeError(f"registry {tuple(REGISTRY)} does not match PLANNERS {PLANNERS}")
