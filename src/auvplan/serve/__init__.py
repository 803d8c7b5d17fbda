"""``auvplan serve``: plan, edit and check a mission in a local web page, offline (issue 41).

:mod:`.session` holds what one page works on (the scenario, the waypoints, the candidates, the
history), :mod:`.actions` what its requests do (one module per group), and :mod:`.app` maps the page's
requests onto a session (Starlette).  The work the page asks for is the jobs' (:mod:`auvplan.app.page`:
the incremental ``mission check`` and energy budget, the survey, plan and flight, file access confined to
the folders the server was started with; :mod:`auvplan.app.results`: the results folder).  Nothing here
evaluates code sent by the page: requests are JSON data, checked by the same loaders as the command line.
"""

from __future__ import annotations

__all__: list[str] = []
