"""``auvplan serve``: plan, edit and check a mission in a local web page, offline (issue 41).

:mod:`.check` re-runs ``mission check`` incrementally as the mission is edited, :mod:`.session`
holds what one page works on (the scenario, the waypoints, the candidates, the history),
:mod:`.plans` asks the survey planner, the planners and the simulator for a survey, a plan, a flight,
:mod:`.paths` confines file access to the folders the server was started with, :mod:`.save` writes
the chosen mission as a normal results folder, and :mod:`.app` maps the page's requests onto a
session (Starlette).  Nothing here evaluates code sent by the page: requests are JSON data, checked
by the same loaders as the command line.
"""

from __future__ import annotations

__all__: list[str] = []
