"""The routes of ``auvplan serve`` (Starlette): the page, its assets, and a JSON API over a :class:`Session`.

Every asset is served from the package (plotly.js from the installed plotly), so the page works with
no network.  Requests carry JSON data only; errors come back as ``{"error": line}`` with the line
the command line prints for the same input (status 400), never a traceback.

* ``GET /`` the page; ``GET /static/<name>`` its script, style sheet and plotly.js;
* ``GET /api/state`` scenario, waypoints, check, candidates, history, flight;
* ``GET /api/chart`` the plan view (the report's chart, :func:`auvplan.viz.chart.figure_plan_view`);
* ``POST /api/edit`` ``{op, index, x, y, z}``; ``POST /api/undo``; ``POST /api/check`` ``{semantics, pitch}``;
* ``POST /api/set`` ``{table, key, value}``; ``POST /api/open`` ``{scenario}``;
* ``POST /api/survey`` ``{polygon}`` or ``{file}``; ``POST /api/plan`` ``{planner, seed}``; ``POST /api/fly``;
  ``POST /api/stop`` (the running plan or flight stops at its next step: its request answers 409);
* ``POST /api/keep`` ``{name}``; ``POST /api/choose`` ``{index}``; ``POST /api/save`` ``{name}``.
"""

from __future__ import annotations

import json
import math
from collections.abc import Awaitable, Callable
from importlib import resources
from typing import Any

import anyio
import numpy as np
from starlette.applications import Starlette
from starlette.middleware import Middleware
from starlette.middleware.trustedhost import TrustedHostMiddleware
from starlette.requests import Request
from starlette.responses import HTMLResponse, JSONResponse, Response
from starlette.routing import Route

from ..app.page.check import CheckResult
from ..errors import AuvplanError
from ..sim import RunRecord
from .actions import editing, planning, scenario
from .delta import Revisions, StaleRevision
from .session import Busy, Session, Stopped, Superseded, builtin_names

__all__ = ["make_app", "page_state", "one_line", "bounded_body", "ClientGone", "MAX_BODY_BYTES", "LOCAL_HOSTS",
           "WRITER_THREADS"]

LOCAL_HOSTS = ("127.0.0.1", "localhost")
"""``Host`` names accepted by default (tests pass their client's name, ``testserver``, themselves)."""

MAX_BODY_BYTES = 4 * 1024 * 1024
"""Largest request body (a 20 000-point polygon is well under)."""

MAX_ERROR_CHARS = 2000
"""Longest error line a request is answered with (the value it quotes cut)."""

WRITER_THREADS = 4
"""Threads the POST requests share (they take turns on the session's ``write_lock`` anyway): a burst of them
waits in this queue, not in the thread pool that ``GET /api/state`` and ``/api/chart`` are answered from."""

_STATIC = {"app.js": "text/javascript", "delta.js": "text/javascript", "app.css": "text/css"}
"""Assets of the page, by name (nothing else under /static is served)."""


def one_line(exc: BaseException) -> str:
    """The error line the command line prints for ``exc`` (``auvplan: error: ...``).

    Parameters
    ----------
    exc : BaseException
        The error.

    Returns
    -------
    str
        One line, multi-line messages folded.
    """
    text = " ".join(str(exc).split())
    if not (isinstance(exc, AuvplanError) and text):
        text = f"{type(exc).__name__}: {text}" if text else type(exc).__name__
    if len(text) > MAX_ERROR_CHARS:  # a 4 MB planner name came back whole in the error (hostile round 20)
        text = f"{text[:MAX_ERROR_CHARS]}… ({len(text):,} characters)"
    # a lone surrogate quoted (JSON's "\ud800") cannot be encoded: the answer failed, HTTP 500 (hostile round 22)
    text = text.encode("utf-8", "backslashreplace").decode("utf-8")
    return f"auvplan: error: {text}"


def _clean(v: Any) -> Any:
    """JSON-safe: non-finite floats as null, arrays as lists."""
    if isinstance(v, dict):
        return {str(k): _clean(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_clean(x) for x in v]
    if isinstance(v, np.ndarray):
        if v.dtype.kind == "f" and np.isfinite(v).all():
            return v.tolist()  # the waypoints: finite by construction, no walk through them
        return _clean(v.tolist())
    if isinstance(v, (np.floating, float)):
        f = float(v)
        return f if math.isfinite(f) else None
    if isinstance(v, np.integer):
        return int(v)
    if isinstance(v, np.bool_):
        return bool(v)
    return v


def _check_json(result: CheckResult | None, whole: bool = True) -> dict[str, Any] | None:
    if result is None:
        return None
    out: dict[str, Any] = {"summary": result.summary, "rechecked": result.rechecked}
    if whole:  # else the violations come as a splice (``delta``) and the page does not need the legs' figures
        out.update(violations=result.violations, leg_altitude_m=result.check.leg_altitude_m)
    return out


def page_state(session: Session, full: bool = True, revisions: Revisions | None = None,
               known: Any = None) -> dict[str, Any]:
    """What the page shows, as JSON data.

    Parameters
    ----------
    session : Session
        The session.
    full : bool, optional
        Also the scenario text, settings, candidates and history (else the mission and its check only).
    revisions : Revisions, optional
        The session's waypoint revisions: with ``known`` (the revision the page holds), the waypoints
        come as the splice ``delta`` from it, and so do the check's violations (the per-leg altitudes
        are then left out).
    known : int, optional
        The page's revision (``rev`` of its request).

    Returns
    -------
    dict
        JSON-safe state.
    """
    with session.lock:
        result = session.result
        wp = ({"waypoints": session.waypoints} if revisions is None or result is None
              else revisions.state(session.waypoints, result.violations, known))
        state: dict[str, Any] = {"generation": session.generation, **wp,
                                 "keys": session.keys,
                                 "check": _check_json(result, "waypoints" in wp), "history": session.history[-50:],
                                 "candidates": session.candidate_rows(), "flight": session.flight_summary(),
                                 "survey_area": session.survey_area, "nav_band": session.nav_band, "settings": {
                                     "semantics": session.settings.semantics, "pitch_deg": session.settings.pitch_deg}}
        if full and session.sc is not None and session.mission is not None:
            v = session.mission.vehicle
            state.update(scenario=session.sc.name, source=session.source, text=session.text,
                         builtins=builtin_names(), planner=session.mission.planner.name,
                         vehicle={k: getattr(v, k) for k in ("speed", "max_pitch_deg", "turn_radius_m",
                                                             "max_depth_m")},
                         mission={"min_altitude_m": session.world.margins.min_altitude if session.world else None,
                                  "start_time": session.sc.mission.start_time},
                         roots=[str(r) for r in session.roots.folders])
    return _clean(state)  # type: ignore[no-any-return]


def _chart(session: Session) -> str:
    from ..io.data.geo import LocalFrame
    from ..viz.chart import figure_plan_view

    with session.lock:  # the world is never changed in place: drawn outside the lock
        world, sc = session.world, session.sc
    if world is None or sc is None:
        raise AuvplanError("no scenario is open")
    empty = np.empty((0, 3))
    to_lonlat = LocalFrame(*world.origin).inverse if world.origin is not None else None
    fig = figure_plan_view(world, RunRecord(sc.name, sc.seed, None, empty, empty, None), to_lonlat)
    land = world.land
    if land is not None and not land.is_empty:
        import plotly.graph_objects as go
        import shapely

        for i, poly in enumerate(shapely.get_parts(land.geometry)):
            xy = np.asarray(poly.exterior.coords)
            fig.add_trace(go.Scatter(x=xy[:, 0], y=xy[:, 1], mode="lines", fill="toself", name="land",
                                     legendgroup="land", showlegend=i == 0, line=dict(color="saddlebrown", width=1),
                                     fillcolor="rgba(160,120,60,0.6)", hoverinfo="skip"))
    fig.update_layout(height=680, title=None, margin=dict(l=60, r=10, t=30, b=40), uirevision="chart")
    return str(fig.to_json())


def _index(d: dict[str, Any]) -> int:
    v = d.get("index")
    if isinstance(v, bool) or not isinstance(v, int):
        raise AuvplanError(f"index {v!r}: not an integer")
    return v


Handler = Callable[[Request], Awaitable[Response]]


class ClientGone(AuvplanError):
    """The client closed the connection before its request's body was read (nothing to answer)."""


async def bounded_body(request: Request, limit: int) -> bytes:
    """The request's body, read chunk by chunk and refused as soon as it passes ``limit`` bytes.

    A declared ``Content-Length`` over the limit is refused before a byte is read; a body without one
    (chunked) is counted as it streams, so a 300 MB body never sits in memory.

    Parameters
    ----------
    request : starlette.requests.Request
        The request.
    limit : int
        Largest body (bytes).

    Returns
    -------
    bytes
        The body.
    """
    from starlette.requests import ClientDisconnect

    declared = request.headers.get("content-length", "")
    if declared.isdigit() and int(declared) > limit:
        raise AuvplanError(f"request of {int(declared):,} bytes, over the {limit:,} allowed")
    chunks, size = [], 0
    try:
        async for chunk in request.stream():
            size += len(chunk)
            if size > limit:
                raise AuvplanError(f"request of more than {limit:,} bytes, over the {limit:,} allowed")
            chunks.append(chunk)
    except ClientDisconnect:
        raise ClientGone("the client closed the connection") from None
    return b"".join(chunks)


def _page_routes() -> list[Route]:
    """The page, its assets and the favicon (served from the package)."""
    static = resources.files("auvplan.serve") / "static"

    async def index(request: Request) -> Response:
        return HTMLResponse((static / "index.html").read_text(encoding="utf-8"),
                            headers={"Content-Security-Policy": "default-src 'self'; style-src 'self' 'unsafe-inline'; "
                                     "img-src 'self' data: blob:; script-src 'self' 'unsafe-eval'"})

    async def asset(request: Request) -> Response:
        name = request.path_params["name"]
        if name == "plotly.min.js":
            from plotly.offline import get_plotlyjs

            return Response(get_plotlyjs(), media_type="text/javascript")
        if name not in _STATIC:
            return JSONResponse({"error": f"auvplan: error: /static/{name}: no such asset"}, status_code=404)
        return Response((static / name).read_text(encoding="utf-8"), media_type=_STATIC[name])

    return [
        Route("/", index),
        Route("/static/{name}", asset),
        Route("/favicon.ico", lambda request: Response(status_code=204)),
    ]


async def _json_body(request: Request) -> dict[str, Any]:
    """The request's JSON object (``{}`` for an empty body); refused unless it says it is JSON."""
    if request.headers.get("content-type", "").split(";")[0].strip().lower() != "application/json":
        raise AuvplanError("the request must be JSON (Content-Type: application/json)")
    raw = await bounded_body(request, MAX_BODY_BYTES)
    if not raw:
        return {}
    try:
        data = json.loads(raw)
    except (ValueError, RecursionError):
        raise AuvplanError("the request is not JSON") from None
    if not isinstance(data, dict):
        raise AuvplanError("the request must be a JSON object")
    return data


def _api(session: Session, revisions: Revisions, writers: anyio.CapacityLimiter,
         work: Callable[[dict[str, Any]], Any], full: bool = False) -> Handler:
    """The handler of one API route: ``work`` on the request's data in a worker thread, answered with the state."""
    def answer(data: dict[str, Any]) -> Any:  # in a worker thread: the event loop never waits on a lock
        out = work(data)
        if isinstance(out, Response):
            return out
        state = page_state(session, full, revisions, data.get("rev"))
        if out is not None:
            state["result"] = _clean(out)
        return state

    async def handler(request: Request) -> Response:
        try:
            data = await _json_body(request) if request.method == "POST" else {}
            # writers queue on their own few threads: the readers (state, chart) always find one free
            out = await anyio.to_thread.run_sync(answer, data,
                                                 limiter=writers if request.method == "POST" else None)
        except ClientGone:
            return Response(status_code=400)  # nobody reads it; no traceback in the server's log
        except StaleRevision as exc:  # an edit on an old picture: not applied, the page reloads the state
            return JSONResponse({"error": one_line(exc), "stale": True}, status_code=409)
        except Superseded as exc:  # long work overtaken by an edit: dropped, the edit stands
            return JSONResponse({"error": one_line(exc), "superseded": True}, status_code=409)
        except Stopped as exc:  # long work stopped on the page's request (/api/stop)
            return JSONResponse({"error": one_line(exc), "stopped": True}, status_code=409)
        except Busy as exc:  # long work already running: refused at once, never queued
            return JSONResponse({"error": one_line(exc), "busy": True}, status_code=503,
                                headers={"Retry-After": "1"})
        except (AuvplanError, ValueError, OSError, KeyError, TypeError, MemoryError, RecursionError,
                OverflowError, IndexError) as exc:
            return JSONResponse({"error": one_line(exc)}, status_code=400)
        if isinstance(out, Response):
            return out
        return JSONResponse(out)

    return handler


def _api_routes(session: Session, revisions: Revisions, writers: anyio.CapacityLimiter) -> list[Route]:
    """The JSON API's routes over ``session`` (:func:`_api` makes each handler)."""
    def api(work: Callable[[dict[str, Any]], Any], full: bool = False) -> Handler:
        return _api(session, revisions, writers, work, full)

    def current(d: dict[str, Any]) -> None:
        """Refuse an edit made on another revision than the session's (the caller holds the lock)."""
        result = session.result
        revisions.require(d.get("rev"), session.waypoints, result.violations if result is not None else [])

    def edit(d: dict[str, Any]) -> None:
        with session.write_lock:
            current(d)
            editing.edit(session, str(d.get("op")), d.get("index"), d.get("x"), d.get("y"), d.get("z"))

    def undo(d: dict[str, Any]) -> None:
        with session.write_lock:
            current(d)
            editing.undo(session)

    def chart(d: dict[str, Any]) -> Response:
        return Response(_chart(session), media_type="application/json")

    def save(d: dict[str, Any]) -> dict[str, str]:
        from .actions.save import save_results

        with session.long_work("saving the results"):
            out = save_results(session, d.get("name", ""))
        return {"saved": str(out)}

    return [
        Route("/api/state", api(lambda d: None, full=True)),
        Route("/api/chart", api(chart)),
        Route("/api/edit", api(edit), methods=["POST"]),
        Route("/api/undo", api(undo), methods=["POST"]),
        Route("/api/check", api(lambda d: editing.set_check(session, d.get("semantics", "held"),
                                                            d.get("pitch", 15.0)) and None), methods=["POST"]),
        Route("/api/set", api(lambda d: scenario.set_value(session, str(d.get("table")), str(d.get("key")),
                                                           d.get("value")) and None, full=True), methods=["POST"]),
        Route("/api/open", api(lambda d: scenario.open_scenario(session, str(d.get("scenario", ""))), full=True),
              methods=["POST"]),
        Route("/api/survey", api(lambda d: planning.survey(session, d.get("polygon"), d.get("file")) and None,
                                 full=True), methods=["POST"]),
        Route("/api/plan", api(lambda d: planning.replan(session, d.get("planner") or None, d.get("seed"))
                               and None), methods=["POST"]),
        Route("/api/fly", api(lambda d: planning.fly(session)), methods=["POST"]),
        Route("/api/stop", api(lambda d: planning.stop(session)), methods=["POST"]),
        Route("/api/keep", api(lambda d: editing.keep(session, d.get("name", "")) and None), methods=["POST"]),
        Route("/api/choose", api(lambda d: editing.choose(session, _index(d)) and None), methods=["POST"]),
        Route("/api/save", api(save), methods=["POST"]),
    ]


def make_app(session: Session, hosts: tuple[str, ...] = LOCAL_HOSTS) -> Starlette:
    """The Starlette application of a session.

    Requests whose ``Host`` is not one of ``hosts`` are refused (a web page elsewhere cannot reach the
    server through a DNS name pointed at 127.0.0.1), and a POST must say it is JSON (``Content-Type:
    application/json``), which a page of another origin cannot send without the browser asking the
    server first (it is never allowed): no other site can edit or save through your browser.

    Parameters
    ----------
    session : Session
        The page's state (one per server: the page is for one user on this machine).
    hosts : tuple of str, optional
        Host names the page is served under (``--host`` adds its address).

    Returns
    -------
    starlette.applications.Starlette
        The ASGI application.
    """
    routes = _page_routes() + _api_routes(session, Revisions(), anyio.CapacityLimiter(WRITER_THREADS))
    return Starlette(routes=routes, middleware=[Middleware(TrustedHostMiddleware, allowed_hosts=list(hosts))])
