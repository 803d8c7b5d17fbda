"""Long actions: survey an area, plan again, fly the mission.

Each runs aside (:meth:`~auvplan.serve.session.Session.long_work`: a second one is answered ``busy`` at
once) with no lock held while it computes; its result is committed only if the mission was not edited
meanwhile (:meth:`~auvplan.serve.session.Session.require_epoch`: else it is dropped, the edit wins).  A plan
or a flight stops at its next step when the page asks (:func:`stop`, ``POST /api/stop``).
"""

from __future__ import annotations

from typing import Any

from ...app.page.check import CheckResult
from ...app.page.plans import flown, plan_area, replanned, survey_table
from ...io.files import limits as _limits
from ..session import Session

__all__ = ["survey", "plan_survey", "replan", "fly", "stop"]


def survey(session: Session, polygon_xy: Any = None, file: str | None = None) -> CheckResult:
    """Make the mission a survey of an area drawn on the chart (local x, y) or read from a file.

    Parameters
    ----------
    session : Session
        The page's state.
    polygon_xy : array_like, optional
        ``(K, 2)`` polygon in the local frame (m).
    file : str, optional
        GeoJSON or KML file inside the served folders (its largest polygon).

    Returns
    -------
    CheckResult
        The check of the survey mission.
    """
    with session.long_work("a survey") as epoch:
        session.require()
        path = session.roots.resolve(file) if file else None
        doc = survey_table(session.doc, None if path else polygon_xy, path)
        what = f"the area of {file}" if file else f"a drawn area of {len(doc['survey']['polygon_xy'])} points"
        return plan_survey(session, doc, what, epoch)


def plan_survey(session: Session, doc: dict[str, Any], what: str, epoch: int | None = None) -> CheckResult:
    """Plan the survey of ``doc`` (no lock held) and make it the mission, unless an edit came meanwhile.

    Parameters
    ----------
    session : Session
        The page's state.
    doc : dict
        The scenario document with its ``[survey]``.
    what : str
        The area, for the history.
    epoch : int, optional
        :meth:`Session.long_work`'s epoch (None: the caller holds ``write_lock`` throughout).

    Returns
    -------
    CheckResult
        The check of the survey mission.
    """
    with session.lock:
        world, mission = session.require()
        source, base = session.source, session.base_dir
    s = plan_area(world, mission, doc, source, base, session.roots)  # aside: no lock held
    with session.write_lock:
        if epoch is not None:
            session.require_epoch(epoch, "the survey")
        _limits.check_route_endurance("serve: the survey", s.route, mission.endurance.ds_m)
        with session.lock:
            session.doc, session.text, session.sc = s.doc, s.text, s.scenario
            session.survey_area, session.plan = s.area, None
        result = session.apply(s.route, "survey", f"survey of {what}: {s.label}")
        session.keep_current("survey", "survey", None)
        return result


def replan(session: Session, planner: str | None = None, seed: int | None = None) -> CheckResult:
    """Plan the mission again (global plan → executable mission) and keep it as a candidate.

    Parameters
    ----------
    session : Session
        The page's state.
    planner : str, optional
        A registered planner (the scenario's by default).
    seed : int, optional
        Seed (the scenario's by default).

    Returns
    -------
    CheckResult
        The check of the new mission (it becomes the current one).
    """
    with session.long_work("a plan") as epoch:
        with session.lock:
            world, mission = session.require()
            name = planner or mission.planner.name
            s = (session.sc.seed if session.sc else 0) if seed is None else seed
        plan, route = replanned(world, mission, name, s,
                                lambda *_: session.stop_point(f"the plan with {name} seed {s}"))
        with session.write_lock:
            session.require_epoch(epoch, f"the plan with {name}")
            with session.lock:
                session.plan = plan
            result = session.apply(route, "plan", f"planned with {name} seed {s}: {route.shape[0]} waypoints")
            session.keep_current(f"{name} seed {s}", name, plan)
            return result


def fly(session: Session) -> None:
    """Fly the current mission in the closed loop (currents, moving obstacles, the guidance).

    Parameters
    ----------
    session : Session
        The page's state.
    """
    with session.long_work("a flight"):
        with session.lock:
            world, mission = session.require()
            w = session.waypoints.copy()
            seed = session.sc.seed if session.sc else 0
        sim = flown(world, mission, w, seed, lambda *_: session.stop_point("the flight"))
        with session.lock:
            session.flight, session.flight_of = sim, w
        session.record("fly", f"flew the mission: {sim.status.value}")


def stop(session: Session) -> dict[str, str]:
    """Stop the running plan or flight (:meth:`~auvplan.serve.session.Session.stop`); its request answers 409.

    Parameters
    ----------
    session : Session
        The page's state.

    Returns
    -------
    dict
        ``stopping``: what was asked to stop ('' when nothing ran).
    """
    return {"stopping": session.stop()}
