"""``auvplan serve [SCENARIO | RESULTS_DIR] [--port N] [--no-browser]``: the local planning page.

Opens a scenario (a built-in name or a TOML file) or a results folder in a :class:`~auvplan.serve.session.Session`
and serves the page on ``127.0.0.1`` (another address only with ``--host``), opening it in the
browser unless ``--no-browser``.  The page reads and saves files only inside the folder of what it
was started with (``--root`` adds folders).
"""

from __future__ import annotations

import argparse
import sys
import threading
import time
import webbrowser
from pathlib import Path
from typing import Any

from ..errors import AuvplanError, require

__all__ = ["cmd_serve", "DEFAULT_HOST", "served_folders", "server_config", "make_session"]

DEFAULT_SCENARIO = "showcase"
"""Opened when no SCENARIO is given (the built-in default scenario, as ``auvplan demo`` runs)."""

DEFAULT_HOST = "127.0.0.1"
"""The page is served on this machine only unless ``--host`` says otherwise."""


def served_folders(target: str | None, roots: list[str] | None) -> list[Path]:
    """The folders the page may read and save in: ``--root`` folders, else the results folder, the
    scenario file's folder, or the current folder (for a built-in scenario).

    Parameters
    ----------
    target : str or None
        SCENARIO or RESULTS_DIR.
    roots : list of str or None
        ``--root`` folders.

    Returns
    -------
    list of pathlib.Path
        Existing folders.
    """
    if roots:
        folders = [Path(r) for r in roots]
    elif target and Path(target).is_dir():
        folders = [Path(target)]
    elif target and Path(target).is_file():
        folders = [Path(target).resolve().parent]
    else:
        folders = [Path.cwd()]
    for f in folders:
        if not f.is_dir():
            raise AuvplanError(f"--root {f}: not a folder")
    return folders


def make_session(target: str | None, roots: list[str] | None = None) -> Any:
    """A session serving ``target`` (default: the built-in default scenario) confined to its folders.

    Parameters
    ----------
    target : str or None
        SCENARIO or RESULTS_DIR.
    roots : list of str, optional
        ``--root`` folders.

    Returns
    -------
    auvplan.serve.session.Session
        The opened session.
    """
    from ..app.page.paths import Roots
    from ..serve.actions.scenario import open_scenario
    from ..serve.session import Session

    folders = served_folders(target, roots)
    session = Session(Roots.of(folders))
    name = target or DEFAULT_SCENARIO
    p = Path(name)
    open_scenario(session, str(p.resolve()) if p.exists() else name)
    return session


def server_config(app: Any, host: str = DEFAULT_HOST, port: int = 8765) -> Any:
    """The uvicorn configuration of the page's server.

    Parameters
    ----------
    app : ASGI application
        :func:`auvplan.serve.app.make_app`'s.
    host : str, optional
        Address to bind (this machine only by default).
    port : int, optional
        TCP port (0: any free port).

    Returns
    -------
    uvicorn.Config
        The configuration.
    """
    import uvicorn

    return uvicorn.Config(app, host=host, port=port, log_level="warning", access_log=False, lifespan="off",
                          server_header=False, proxy_headers=False)


def _port_free(host: str, port: int) -> int:
    """Refuse an address this machine cannot serve on, or a port another program listens on, before the scenario
    is loaded; returns the port (``--port 0``: a free one, chosen here so that the page's address printed is the
    real one, not ``:0``).  ``--port 0`` is tried too; a fault of the address
    names ``--host`` (it named ``--port``; with ``--port 0`` uvicorn's own 'ERROR: [Errno -2] Name or service not
    known' came after the 'serving on' line, exit 3: hostile round 20)."""
    import errno
    import socket

    if not host.strip():  # '' listens on every interface
        raise AuvplanError(f"--host {host!r}: an empty address; --host 0.0.0.0 serves on every interface")
    try:
        with socket.create_server((host, port), family=_family(host)) as sock:
            return int(sock.getsockname()[1])
    except OSError as exc:
        why = exc.strerror or str(exc)
        if exc.errno is None or exc.errno < 0 or exc.errno in (errno.EADDRNOTAVAIL, errno.EAFNOSUPPORT, errno.EINVAL):
            # (a name that does not resolve: getaddrinfo's negative codes, which create_server passes on)
            raise AuvplanError(f"--host {host!r}: cannot serve on this address ({why}); give an address of this "
                               "machine, e.g. 127.0.0.1") from None
        raise AuvplanError(f"--port {port}: cannot serve on {host}:{port} ({why}); choose another --port") from None


def _loopback(host: str) -> bool:
    """Whether ``host`` is this machine only (``localhost``, 127.0.0.0/8, ``::1``)."""
    import ipaddress

    try:
        return host == "localhost" or ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def _family(host: str) -> Any:
    """``AF_INET6`` for an IPv6 literal, else ``AF_INET``."""
    import socket

    return socket.AF_INET6 if ":" in host else socket.AF_INET


def cmd_serve(args: argparse.Namespace) -> int:
    """Run the serve command until interrupted.

    Parameters
    ----------
    args : argparse.Namespace
        ``target``, ``port``, ``host``, ``root``, ``no_browser``.

    Returns
    -------
    int
        0 after a clean stop.
    """
    require("starlette", "serve")
    require("uvicorn", "serve")
    require("plotly", "serve")
    import uvicorn

    from ..serve.app import LOCAL_HOSTS, make_app

    port = _port_free(args.host, args.port)
    if args.host != DEFAULT_HOST and not _loopback(args.host):
        print(f"auvplan: warning: serving on {args.host}: anyone who can reach this address can edit and save "
              "missions in the served folders", file=sys.stderr)
    session = make_session(args.target, args.root)
    hosts = LOCAL_HOSTS if args.host == DEFAULT_HOST else (*LOCAL_HOSTS, args.host)
    server = uvicorn.Server(server_config(make_app(session, hosts), args.host, port))
    url = f"http://{f'[{args.host}]' if ':' in args.host else args.host}:{port}/"
    print(f"auvplan serve: {session.sc.name if session.sc else ''} on {url} (folders: "
          f"{', '.join(map(str, session.roots.folders))}); Ctrl-C stops", file=sys.stderr)
    if not args.no_browser:  # once the server listens
        threading.Thread(target=_open_when_started, args=(server, url), daemon=True).start()
    server.run()
    return 0


def _open_when_started(server: Any, url: str, timeout: float = 60.0) -> None:
    t0 = time.monotonic()
    while not server.started and not server.should_exit and time.monotonic() - t0 < timeout:
        time.sleep(0.05)
    if server.started:
        webbrowser.open(url)
