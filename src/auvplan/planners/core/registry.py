"""The planner registry: the one plug-in point of the global planners (after OMPL's planner factory
and robotics-toolbox's planner classes).

A planner is a function ``run(problem, spec, rng, progress) -> PlanResult``: the
:class:`~auvplan.planners.core.base.PlanningProblem` (world, end points, vehicle figures) as one
object, the :class:`~auvplan.planners.core.base.PlannerSpec` (its settings), a seed or generator and
an optional ``progress(iteration, best_cost)``.  A deterministic planner that neither draws nor
iterates registers its ``plan(problem, spec)`` (or ``plan(problem, settings)``) with ``deterministic`` set,
and the registry calls it under that signature (:func:`deterministic_run`).  :func:`register` adds one
under a name, with the frozen dataclass of its settings; from then on

- :class:`~auvplan.planners.core.base.PlannerSpec` accepts the name (``[planner] name = "..."``),
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
from typing import Any, Literal

__all__ = ["PlannerEntry", "REGISTRY", "register", "get", "names", "known", "load_plugins", "ENTRY_POINTS",
           "PLANNERS", "SWARM", "PIPELINES", "CAPABILITIES", "has", "Deterministic", "deterministic_run"]

PlannerFn = Callable[..., Any]
"""``run(problem, spec, rng, progress) -> PlanResult``."""

Deterministic = Literal["spec", "settings"]
"""What a deterministic planner's ``plan`` takes besides the problem: the whole
:class:`~auvplan.planners.core.base.PlannerSpec` (``"spec"``) or only its own settings (``"settings"``,
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

CAPABILITIES = {
    "path_cost": "its result's cost is the project's path cost (length + terrain + energy, auvplan.cost), so a "
                 "repaired path is re-costed by that cost and no other",
    "currents": "its cost or its timing accounts for the world's currents",
    "time_varying": "it plans in currents that change with time (a departure time and timed waypoints)",
    "zones": "it keeps out of the world's charted no-go zones ([[zones]]); a planner without it is refused in a "
             "world that has any (auvplan.planners.plan)",
}
"""What a planner may declare at registration (:func:`register`'s ``capabilities``), and what each means.
The rest of the package asks :func:`has`, never a planner's name."""


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
        Where :class:`~auvplan.planners.core.base.PlannerSpec` keeps those settings: the attribute of a
        built-in planner (``"flow"``, ``"iabc"`` …); None for a planner registered from outside,
        whose ``[planner.<name>]`` table :meth:`PlannerSpec.params_for` returns.
    deterministic : {"spec", "settings"} or None
        None: ``target`` is ``run(problem, spec, rng, progress)``.  Otherwise ``target`` is a deterministic
        ``plan(problem, spec)`` (``"spec"``) or ``plan(problem, settings)`` (``"settings"``), which
        :attr:`run` calls under the registry's signature (:func:`deterministic_run`).
    capabilities : frozenset of str
        What it declares it does (keys of :data:`CAPABILITIES`).
    """

    name: str
    target: PlannerFn | str
    iterative: bool
    description: str
    params: type | str | None = None
    table: str | None = None
    deterministic: Deterministic | None = None
    capabilities: frozenset[str] = frozenset()

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
    unknown = sorted(entry.capabilities - CAPABILITIES.keys())
    if unknown:
        raise ValueError(f"planner {entry.name!r}: capabilities {unknown} unknown; choose from "
                         f"{', '.join(CAPABILITIES)}")
    if entry.name in REGISTRY:
        raise ValueError(f"planner {entry.name!r} is already registered")
    REGISTRY[entry.name] = entry


def register(name: str, *, iterative: bool, description: str, params: type | str | None = None,
             deterministic: Deterministic | None = None, capabilities: tuple[str, ...] = (),
             table: str | None = None) -> Callable[[PlannerFn | str], PlannerFn | str]:
    """Decorator: register ``run(problem, spec, rng, progress)`` as planner ``name`` (or, with
    ``deterministic``, a ``plan(problem, spec)`` or ``plan(problem, settings)``).

    The built-in planners register through it too, applied to the ``"module:function"`` path of their
    function (imported when first run) instead of the function itself.

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
    capabilities : tuple of str, optional
        What the planner does (keys of :data:`CAPABILITIES`); the package asks :func:`has`.
    table : str, optional
        Built-in planners only: the :class:`~auvplan.planners.core.base.PlannerSpec` attribute that holds
        their settings (``"iabc"``, ``"flow"`` …).

    Returns
    -------
    callable
        The decorator; it returns the function (or path) unchanged.

    Raises
    ------
    ValueError
        If ``name`` is already registered or is not an identifier, a capability is unknown, or
        ``deterministic`` is not one of the two forms or comes with ``iterative`` (when the decorator is
        applied).
    """

    def add(run: PlannerFn | str) -> PlannerFn | str:
        _add(PlannerEntry(name, run, iterative, description, params, table, deterministic, frozenset(capabilities)))
        return run

    return add


def has(name: str, capability: str) -> bool:
    """Whether the planner ``name`` declared ``capability`` at registration.

    Parameters
    ----------
    name : str
        A registered planner name.
    capability : str
        A key of :data:`CAPABILITIES`.

    Returns
    -------
    bool
        True when it declared it; False for an unknown planner name (a result with no planner).

    Raises
    ------
    ValueError
        If ``capability`` is not a key of :data:`CAPABILITIES`.
    """
    if capability not in CAPABILITIES:
        raise ValueError(f"unknown capability {capability!r}; choose from {', '.join(CAPABILITIES)}")
    return known(name) and capability in REGISTRY[name].capabilities


def load_plugins() -> None:
    """Load the planners other packages declare in the entry-point group ``auvplan.planners`` (once)."""
    global _PLUGINS_LOADED
    if _PLUGINS_LOADED:
        return
    _PLUGINS_LOADED = True
    from importlib import metadata  # ~15 ms of imports (email, zipfile …): only when a name is not built in

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
# the built-in planners, through the same register() as outside ones, by the dotted path of their function
for _name, (_text, _params) in _SWARM_TEXT.items():
    register(_name, iterative=True, description=_text, params=_params, table=_name,
             capabilities=("path_cost", "currents", "zones"))("auvplan.planners.swarm.planner:plan_swarm")
register("flow", iterative=False, description="potential-flow streamline from the start (document 000)",
         params="auvplan.planners.core.params:FlowParams", table="flow",
         deterministic="settings")("auvplan.planners.flow.planner:plan_flow")
register("grid", iterative=False, description="lattice reference: Dijkstra cost-to-go, elastic band, B-spline",
         params="auvplan.planners.core.params:GridParams", table="grid", deterministic="spec",
         capabilities=("path_cost", "currents", "zones"))("auvplan.planners.grid.planner:plan_grid")
register("timeopt", iterative=False, description="time-optimal path in tidal currents, departure time given",
         params="auvplan.planners.core.params:TimeoptParams", table="timeopt", deterministic="spec",
         capabilities=("currents", "time_varying", "zones"))("auvplan.planners.timeopt.planner:plan_timeopt")

if tuple(REGISTRY) != PLANNERS:  # pragma: no cover - a programming error
    raise RuntimeError(f"registry {tuple(REGISTRY)} does not match PLANNERS {PLANNERS}")
