"""Issue #32, writing outside ``--out``: names that become paths are checked at load time, every path
written is proven inside its ``--out``, and no write goes through a link at any level below it."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from auvplan import cli
from auvplan.errors import ScenarioError
from auvplan.io.files import outdir
from auvplan.io.files.manifest import written
from auvplan.io.files.outdir import OutputError
from auvplan.io.files.safeio import atomic_write, prepare_out
from auvplan.io.results import records
from auvplan.io.scenario import loader as scenario_io
from auvplan.sim import RunRecord

FORMATION = (Path(__file__).parents[2] / "src" / "auvplan" / "data" / "scenarios" / "chagos-formation.toml").read_text()
assert 'name = "port"' in FORMATION

_SAFE = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,63}")


def _with_vehicle_name(name: str) -> str:
    return FORMATION.replace('name = "port"', f"name = {_toml_string(name)}")


def _toml_string(s: str) -> str:
    """A TOML basic string holding ``s`` exactly (every character escaped as \\uXXXX / \\UXXXXXXXX)."""
    return '"' + "".join(f"\\U{ord(c):08X}" for c in s) + '"'


@pytest.fixture(autouse=True)
def _release_locks():
    yield
    outdir.release_all()


@settings(max_examples=150, deadline=None)
@given(st.one_of(st.text(min_size=0, max_size=70),
                 st.sampled_from(["..", ".", "../x", "a/b", "a\\b", "a\x00b", "x y", ".hidden", "-x", "lead\n",
                                  "a" * 65, "\u00e9t\u00e9", "con", "a..b", "A-1.b_2"])))
def test_vehicle_names_are_safe_folder_names_or_refused_naming_the_key(name):
    """Fuzz: a vehicle name is accepted iff it is a plain folder name (independent oracle: the
    pattern, and it is then exactly one level below ``--out``); refused, the error names the key."""
    text = _with_vehicle_name(name)
    collides = name.lower() in ("lead", "starboard", "figures", "report.html", "scenario.toml", "source.json",
                                "slots.csv", "terrain.npz", "formation.json")
    try:
        sc = scenario_io.loads(text, "f.toml")
    except ScenarioError as exc:
        msg = str(exc)
        assert "\n" not in msg and "f.toml: [[vehicles]] #" in msg and "name = " in msg, msg
        assert not _SAFE.fullmatch(name) or collides
        return
    assert _SAFE.fullmatch(name) and not collides
    assert name in [v.name for v in sc.formation.vehicles]
    out = Path("/results/out")
    assert (out / name).parent == out and name not in (".", "..") and "/" not in name


def test_a_dot_dot_vehicle_is_exit_2_before_any_work(tmp_path, capsys):
    path = tmp_path / "f.toml"
    path.write_text(_with_vehicle_name(".."))
    code = cli.main(["run", str(path), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert "[[vehicles]] #2 name = '..'" in err


def test_scenario_names_with_separators_or_control_characters_are_refused():
    text = FORMATION.replace('name = "chagos-formation"', 'name = "a/../b"')
    with pytest.raises(ScenarioError, match=r"f.toml: name = 'a/../b'"):
        scenario_io.loads(text, "f.toml")
    with pytest.raises(ScenarioError, match="name = 'x\\\\ny'"):
        scenario_io.loads(FORMATION.replace('name = "chagos-formation"', 'name = "x\\ny"'), "f.toml")
    assert scenario_io.loads(FORMATION.replace('name = "chagos-formation"', 'name = "my survey (2)"'),
                             "f.toml").name == "my survey (2)"


def _tiny_record() -> RunRecord:
    route = np.array([[0.0, 0.0, -5.0], [10.0, 0.0, -5.0]])
    return RunRecord("s", 0, None, route, route, None)


def test_a_vehicle_folder_that_is_a_link_is_never_written_through(tmp_path):
    out, elsewhere = tmp_path / "out", tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "run.json").write_text("precious")
    out.mkdir()
    (out / "port").symlink_to(elsewhere)
    with pytest.raises(OutputError, match="symbolic link"):
        prepare_out(out, ["formation.json", "port/run.json"])
    assert not outdir.held(out) and not (out / outdir.LOCK).exists()  # refused: no lock kept, none left behind
    outdir.acquire(out)  # locked, as by a prepare_out that passed
    with pytest.raises(OutputError, match="port: is a symbolic link below the output folder"):
        records.write_run(out / "port", _tiny_record())  # a writer that skipped prepare_out's check
    assert sorted(p.name for p in elsewhere.iterdir()) == ["run.json"]
    assert (elsewhere / "run.json").read_text() == "precious"
    prepare_out(out, ["formation.json", "port/run.json"], force=True)  # the link itself is replaced
    records.write_run(out / "port", _tiny_record())
    assert (out / "port").is_dir() and not (out / "port").is_symlink()
    assert (elsewhere / "run.json").read_text() == "precious"
    assert "run.json" in written(out / "port")


def test_a_link_two_levels_down_is_refused_too(tmp_path):
    out, elsewhere = tmp_path / "out", tmp_path / "elsewhere"
    (out / "a").mkdir(parents=True)
    elsewhere.mkdir()
    (out / "a" / "b").symlink_to(elsewhere)
    prepare_out(out, ["x.json"])
    with pytest.raises(OutputError, match="a/b: is a symbolic link"):
        atomic_write(out / "a" / "b" / "c" / "x.json", "1")
    assert list(elsewhere.iterdir()) == []


def test_paths_that_leave_out_are_refused(tmp_path):
    out = tmp_path / "out"
    with pytest.raises(OutputError, match="leaves the output folder"):
        prepare_out(out, ["../run.json"])
    prepare_out(out, ["run.json"])
    with pytest.raises(OutputError, match="outside the output folder"):
        outdir.check_inside(out / ".." / "run.json", out)
    with pytest.raises(OutputError, match="outside the output folder"):
        atomic_write(out / "sub" / ".." / ".." / "run.json", "x")  # as written, not resolved
    assert not (tmp_path / "run.json").exists()


def test_the_resolved_path_must_stay_inside(tmp_path):
    """--out itself may be a link (the user's choice); what lies below it is checked after resolving."""
    real = tmp_path / "real"
    real.mkdir()
    (tmp_path / "out").symlink_to(real)
    prepare_out(tmp_path / "out", ["run.json"])
    atomic_write(tmp_path / "out" / "run.json", "{}")
    assert (real / "run.json").read_text() == "{}"


def test_bench_never_appends_through_a_linked_rows_csv(tmp_path):
    from auvplan.app.bench.sweep import SweepSpec, sweep

    out, victim = tmp_path / "b", tmp_path / "victim.csv"
    out.mkdir()
    victim.write_text("precious\n")
    (out / "rows.csv").symlink_to(victim)
    with pytest.raises(OutputError, match="symbolic link"):
        prepare_out(out, ["rows.csv", "histories.jsonl"])
    with pytest.raises(OutputError, match="rows.csv: is a symbolic link"):
        sweep(SweepSpec(scenarios=("track-single",), seeds=1), out, resume=True, progress=False)
    assert victim.read_text() == "precious\n"
