"""Current ensemble members and perturbation seeds as axes of ``auvplan bench`` (issue 39).

``--members`` names members of the scenario's ``[currents] members`` (``each``: every one); a cell
then plans and flies with that member as the world's only current, exactly as a scenario whose
``[currents]`` is that member alone.  ``--member-seeds`` re-draws the ``perturbation`` entries with
each seed in place of theirs (member j of an entry takes seed + j, as in the scenario).  Like the
avoidance axis, which is written into the guidance column, the member and the seed are written into
the scenario column, ``scenario@member`` or ``scenario@member~seed``, so a cell stays one value of
:data:`~auvplan.app.bench.rows.KEY` and ``--resume`` and the summary work unchanged; the row's ``member``
and ``member_seed`` columns repeat them, and ``arrival_s``, ``member_energy_wh`` and
``member_success`` score the planned route in the member as ``plan --json`` scores its ``members``
(:func:`auvplan.sim.ensemble.score.score_route`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import Any

from ...errors import AuvplanError
from ...io.scenario.inputs.members import scenario_members
from ...io.scenario.specs import Scenario
from ...sim import Mission, RunRecord
from ...world import CurrentField, World

__all__ = ["MEMBER_MARK", "SEED_MARK", "member_label", "parse_label", "scenario_members", "expand_members",
           "member_world", "member_columns"]

MEMBER_MARK = "@"
"""Between the scenario and the member in the scenario column."""

SEED_MARK = "~"
"""Between the member and the perturbation seed in the scenario column."""


def member_label(scenario: str, member: str | None, seed: int | None) -> str:
    """The scenario column of a cell: ``scenario``, ``scenario@member`` or ``scenario@member~seed``.

    Parameters
    ----------
    scenario : str
        Built-in name or TOML file.
    member : str or None
        The member (None: the scenario's own currents).
    seed : int or None
        The perturbation seed (None: the scenario's).

    Returns
    -------
    str
        The label.
    """
    if member is None:
        return scenario
    return f"{scenario}{MEMBER_MARK}{member}" + ("" if seed is None else f"{SEED_MARK}{seed}")


def parse_label(label: str) -> tuple[str, str | None, int | None]:
    """Inverse of :func:`member_label`.

    Parameters
    ----------
    label : str
        A scenario column.

    Returns
    -------
    tuple
        ``(scenario, member or None, seed or None)``.
    """
    scenario, mark, member = label.rpartition(MEMBER_MARK)
    if not mark:
        return label, None, None
    name, smark, seed = member.rpartition(SEED_MARK)
    if smark and seed.isdigit():
        return scenario, name, int(seed)
    return scenario, member, None


def expand_members(scenario: str, sc: Scenario, world: World, members: Sequence[str],
                   seeds: Sequence[int]) -> list[str]:
    """The scenario-column labels of one scenario's cells over the member and seed axes.

    Parameters
    ----------
    scenario : str
        The scenario as the sweep names it (built-in name or TOML file).
    sc : Scenario
        The scenario, loaded.
    world : World
        Its world.
    members : sequence of str
        ``scenario`` (its own currents), ``each`` (every member) or member names.
    seeds : sequence of int
        Perturbation seeds (empty: the scenario's own).

    Returns
    -------
    list of str
        :func:`member_label` of every cell, in order.

    Raises
    ------
    AuvplanError
        A member the scenario does not have, or a member axis on a scenario without members.
    """
    out: list[str] = []
    draws: list[int | None] = list(seeds) or [None]
    for seed in draws:
        have = [n for n, _ in scenario_members(sc, world, seed)]
        for m in members:
            names: list[str | None]
            if m == "scenario":
                names = [None]
            elif not have:
                raise AuvplanError(f"{sc.source}: --members {m}: the scenario has no [currents] members")
            elif m == "each":
                names = list(have)
            elif m in have:
                names = [m]
            else:
                raise AuvplanError(f"{sc.source}: --members {m!r}: no such member; it has {', '.join(have)}")
            for n in names:
                label = member_label(scenario, n, None if n is None else seed)
                if label not in out:
                    out.append(label)
    return out


def member_world(sc: Scenario, world: World, member: str, seed: int | None) -> tuple[World, CurrentField]:
    """The world with one member as its only current.

    Parameters
    ----------
    sc : Scenario
        The scenario.
    world : World
        Its world.
    member : str
        The member's name.
    seed : int or None
        Perturbation seed (None: the scenario's).

    Returns
    -------
    tuple
        The world whose ``currents`` is the member, and the member's field.
    """
    fields = dict(scenario_members(sc, world, seed))
    if member not in fields:
        raise AuvplanError(f"{sc.source}: no current member {member!r}; it has {', '.join(fields) or 'none'}")
    return replace(world, currents=fields[member]), fields[member]


def member_columns(world: World, mission: Mission, record: RunRecord, member: str, seed: int | None,
                   field: CurrentField) -> dict[str, Any]:
    """The row's member columns: the planned route scored in the member as ``plan --json`` does.

    Parameters
    ----------
    world : World
        The world (seabed, obstacles).
    mission : Mission
        Its vehicle.
    record : RunRecord
        The run (its mission route).
    member : str
        The member's name.
    seed : int or None
        Perturbation seed.
    field : CurrentField
        The member's field.

    Returns
    -------
    dict
        ``member``, ``member_seed``, ``arrival_s`` (s; empty without a route, ``inf`` when the current
        beats the vehicle), ``member_energy_wh`` and ``member_success``.
    """
    from ...sim.ensemble.score import score_route

    row: dict[str, Any] = {"member": member, "member_seed": "" if seed is None else seed}
    if record.route is None or len(record.route) < 2:
        return {**row, "arrival_s": "", "member_energy_wh": "", "member_success": False}
    s = score_route(world, [(member, field)], record.route, mission.vehicle).members[0]
    return {**row, "arrival_s": s.arrival_s, "member_energy_wh": s.energy_wh, "member_success": s.success}
