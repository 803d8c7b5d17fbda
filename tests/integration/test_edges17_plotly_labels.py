"""Zone and moving-obstacle names are drawn literally in the report's chart and ``serve``'s (plotly reads ``<b>``,
``<br>``, ``<a href>`` and entities in its texts): the zone's label on the chart, the closest moving obstacle's
hover text, the ensemble members' bars and the page's violation hover (``app.js``) drew a name as markup.  Wave 16
escaped run.json's labels in ``report`` (:func:`auvplan.viz.style.plotly_text`); the same escape is used here."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from auvplan.io.scenario import loader
from auvplan.sim import RunRecord
from auvplan.viz.chart import figure_plan_view
from auvplan.viz.ensemble_view import figure_ensemble

ZONE = "<b>reef</b> & <br>wreck"
MOVER = '<a href="https://example.invalid/x">ferry</a>'
ESCAPED = {ZONE: "&lt;b&gt;reef&lt;/b&gt; &amp; &lt;br&gt;wreck",
           MOVER: '&lt;a href="https://example.invalid/x"&gt;ferry&lt;/a&gt;'}

SCENARIO = f"""
name = "labels"
seed = 1
[bounds]
x = [0.0, 1200.0]
y = [0.0, 800.0]
z = [-100.0, 0.0]
[mission]
start = [100.0, 100.0, -20.0]
goal = [1100.0, 700.0, -20.0]
[[zones]]
name = {json.dumps(ZONE)}
polygon = [[500.0, 200.0], [700.0, 200.0], [700.0, 400.0], [500.0, 400.0]]
[[moving]]
name = {json.dumps(MOVER)}
type = "sphere"
radius = 20.0
motion = "linear"
start = [900.0, 100.0, -20.0]
velocity = [0.0, 1.0, 0.0]
"""


def _texts(fig) -> list[str]:
    """Every text plotly draws as markup in the figure's JSON: trace names, texts, hover texts, annotations."""
    doc = json.loads(fig.to_json())
    out = []
    for tr in doc["data"]:
        for key in ("name", "text", "hovertext"):
            v = tr.get(key)
            out += [str(x) for x in v] if isinstance(v, list) else [str(v)] if v is not None else []
    out += [str(a.get("text", "")) for a in doc["layout"].get("annotations", [])]
    return out


def test_zone_and_moving_obstacle_names_are_escaped_in_the_chart():
    world, mission = loader.build(loader.loads(SCENARIO))
    t = np.linspace(0.0, 600.0, 61)
    pos = np.column_stack([100.0 + 1.5 * t, 100.0 + t, np.full_like(t, -20.0)])
    sim = SimpleNamespace(t=t, position=pos, altitude=np.full_like(t, 80.0))
    route = np.array([mission.start, mission.goal])
    fig = figure_plan_view(world, RunRecord("labels", 1, None, route, route, sim))  # type: ignore[arg-type]
    texts = _texts(fig)
    for raw in ESCAPED:
        assert not any(raw in s for s in texts), raw  # never the markup itself
    assert any(ESCAPED[ZONE] == s for s in texts)  # the zone's label on the chart
    assert any(ESCAPED[ZONE] + ": " in s for s in texts)  # its hover
    assert any(s.startswith(ESCAPED[MOVER] + ", radius 20 m") for s in texts)  # the closest mover's hover


def test_ensemble_member_names_are_escaped():
    fig = figure_ensemble({"members": [{"name": ZONE, "arrival_s": 3600.0, "energy_wh": 10.0, "success": True}],
                           "success_probability": 1.0})
    doc = json.loads(fig.to_json())
    xs = [x for tr in doc["data"] for x in tr["x"]]
    assert xs == [ESCAPED[ZONE]] * 2


APP_JS = Path(__file__).parents[2] / "src" / "auvplan" / "serve" / "static" / "app.js"


def _function(src: str, name: str) -> str:
    """A top-level ``function NAME(...) {...}`` of app.js, by matching braces."""
    i = src.index(f"function {name}(")
    depth, j = 0, src.index("{", i)
    for k in range(j, len(src)):
        depth += {"{": 1, "}": -1}.get(src[k], 0)
        if depth == 0:
            return src[i:k + 1]
    raise AssertionError(name)


@pytest.mark.skipif(shutil.which("node") is None, reason="node is not installed")
def test_the_page_escapes_a_violation_naming_a_zone():
    """``badTraces`` of app.js run in node on the violations the page receives (app/page/check.py's texts)."""
    src = APP_JS.read_text()
    body = "\n".join(_function(src, n) for n in ("plotlyText", "badTraces") if f"function {n}(" in src)
    script = body + (
        "\nconst W = [[0, 0, -5], [100, 0, -5], [200, 0, -5]];"
        f"\nconst S = {{check: {{violations: [{{leg: 0, text: {json.dumps(f'leg 0: enters no-go zone {ZONE!r}')}}}, "
        "{leg: 0, text: 'leg 0: altitude 3.0 m < min_altitude_m = 5'}]}};"
        "\nprocess.stdout.write(JSON.stringify(badTraces().txt));")
    out = subprocess.run(["node", "-e", script], capture_output=True, text=True, timeout=60, check=True).stdout
    (txt,) = json.loads(out)
    assert txt == f"leg 0: enters no-go zone '{ESCAPED[ZONE]}'<br>leg 0: altitude 3.0 m &lt; min_altitude_m = 5"
