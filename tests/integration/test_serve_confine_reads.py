"""``auvplan serve`` refuses a ``[survey] file`` or ``centerline_file`` outside the served folders before it is
read (edges 12: the loader read it to derive the bounds of a geographic scenario, and only then was it refused)."""

from __future__ import annotations

import pytest

pytest.importorskip("starlette")

from auvplan.app.page.paths import PathRefused, Roots  # noqa: E402
from auvplan.errors import ScenarioError  # noqa: E402

_GEO = """name = "geo"
[terrain.synthetic]
kind = "plane"
depth = 200.0
cell_m = 100.0
[mission]
start = {{ lat = 48.0, lon = -125.0, depth = 50.0 }}
goal = {{ lat = 48.01, lon = -124.99, depth = 50.0 }}
[survey]
{key} = "{name}"
"""
_WIDTH = "width_m = 200.0\n"  # a corridor's width (a centre line needs one)


@pytest.fixture
def reads(monkeypatch):
    """Every read of a survey file by the scenario loader (it derives the bounds from the area)."""
    from auvplan.io.scenario.inputs import geoinput

    calls: list[str] = []

    def record(path, *args):
        calls.append(str(path))
        raise ScenarioError(f"{path}: recorded")

    monkeypatch.setattr(geoinput, "read_area_lonlat", record)
    monkeypatch.setattr(geoinput, "read_line_lonlat", record)
    return calls


@pytest.mark.parametrize("key", ["file", "centerline_file"])
@pytest.mark.parametrize("relative", [False, True])
def test_a_survey_file_outside_the_folders_is_refused_unread(tmp_path, reads, key, relative):
    """Oracle: the loader's reader is never called, and the refusal is the usual line naming file, key, value."""
    from auvplan.serve.actions.scenario import open_scenario
    from auvplan.serve.session import Session

    root, outside = tmp_path / "served", tmp_path / "outside"
    root.mkdir()
    outside.mkdir()
    (outside / "area.geojson").write_text("{}")
    name = "../outside/area.geojson" if relative else str(outside / "area.geojson")
    width = _WIDTH if key == "centerline_file" else ""
    (root / "geo.toml").write_text(_GEO.format(key=key, name=name) + width)
    with pytest.raises(PathRefused) as err:
        open_scenario(Session(Roots.of([root])), "geo.toml")
    assert reads == []
    msg = str(err.value)
    assert "\n" not in msg and f"geo.toml: [survey] {key} = {name!r}: outside the served folders" in msg
    (root / "in.geojson").write_text("{}")  # inside: read as before (the control)
    (root / "geo.toml").write_text(_GEO.format(key=key, name="in.geojson") + width)
    with pytest.raises(ScenarioError):
        open_scenario(Session(Roots.of([root])), "geo.toml")
    assert reads and set(reads) == {str(root / "in.geojson")}


def test_the_page_s_survey_of_a_file_outside_is_refused_unread(tmp_path, reads):
    """The page's ``survey`` action (``plan_area``) validates the document with the loader too."""
    import tomllib

    from auvplan.app.page.plans import plan_area

    root, outside = tmp_path / "served", tmp_path / "outside"
    root.mkdir()
    outside.mkdir()
    doc = tomllib.loads(_GEO.format(key="file", name=str(outside / "a.geojson")))
    with pytest.raises(PathRefused, match="outside the served folders"):
        plan_area(None, None, doc, str(root / "geo.toml"), root, Roots.of([root]))
    assert reads == []


def test_the_serve_command_refuses_it_in_one_line_unread(tmp_path, reads, capsys):
    from auvplan.cli import main

    root, outside = tmp_path / "served", tmp_path / "outside"
    root.mkdir()
    outside.mkdir()
    (root / "geo.toml").write_text(_GEO.format(key="file", name=str(outside / "a.geojson")))
    assert main(["serve", str(root / "geo.toml"), "--no-browser"]) == 2
    err = capsys.readouterr().err.strip()
    assert reads == [] and len(err.splitlines()) == 1 and "[survey] file = " in err and "outside the served" in err


def test_a_results_folder_and_a_rebuild_refuse_it_unread(tmp_path, reads, monkeypatch):
    """The two other sites that hand scenario text to the loader: a results folder opened (its stored
    ``scenario.toml``) and a rebuild after a key is set (the session's document)."""
    import tomllib

    from auvplan.io.results import folder, records
    from auvplan.serve.actions import scenario as actions
    from auvplan.serve.session import Session

    root, outside = tmp_path / "served", tmp_path / "outside"
    (root / "run").mkdir(parents=True)
    outside.mkdir()
    text = _GEO.format(key="file", name=str(outside / "a.geojson"))
    monkeypatch.setattr(records, "read_run", lambda out: (None, text))  # the folder's record: only its text is used
    monkeypatch.setattr(folder, "scenario_base", lambda out: out)
    session = Session(Roots.of([root]))
    with pytest.raises(PathRefused, match=r"scenario.toml: \[survey\] file = .*outside the served folders"):
        actions._open_results(session, root / "run")
    session.world, session.source, session.base_dir = object(), str(root / "geo.toml"), root  # as if opened
    with pytest.raises(PathRefused, match="outside the served folders"):
        actions._rebuild(session, tomllib.loads(text))
    assert reads == []


def test_a_results_folder_scenario_whose_source_json_leads_outside_is_refused_unread(tmp_path, reads):
    """A served folder's ``scenario.toml`` with a ``source.json`` beside it (a results folder's, or a hostile one)
    has its relative names resolved by the loader against the folder ``source.json`` names (audit 16: the check
    resolved them against the served folder, then the loader read ``outside/area.geojson``).  Oracle: the reader
    is never called; the refusal names the key."""
    import json

    from auvplan.serve.actions.scenario import open_scenario
    from auvplan.serve.session import Session

    root, outside = tmp_path / "served", tmp_path / "outside"
    root.mkdir()
    outside.mkdir()
    (outside / "area.geojson").write_text("{}")
    (root / "area.geojson").write_text("{}")  # what the served-folder reading of the name would have checked
    (root / "scenario.toml").write_text(_GEO.format(key="file", name="area.geojson"))
    (root / "source.json").write_text(json.dumps({"scenario_source": str(outside / "s.toml")}))
    with pytest.raises(PathRefused, match=r"\[survey\] file = 'area.geojson': outside the served folders"):
        open_scenario(Session(Roots.of([root])), "scenario.toml")
    assert reads == []
