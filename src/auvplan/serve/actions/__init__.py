"""What the page's requests do, one module per group of actions (as a web app keeps its views):
:mod:`.scenario` (open, set a key), :mod:`.editing` (the waypoints, the check's settings, candidates),
:mod:`.planning` (survey, plan, fly: long work run aside) and :mod:`.save` (a results folder).  Each
action takes the :class:`~auvplan.serve.session.Session` (the state) and goes through its commit
primitives."""
