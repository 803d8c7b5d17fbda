"""Current ensemble members and perturbation seeds as ``auvplan bench`` axes (issue 39, point 4).

Oracle: each member's row equals a direct ``auvplan plan --json`` of the scenario with that member as its
only current (``members[0].arrival_s``, ``energy_wh``, ``success``), on the real two-model Lofoten data
(a 1.6 km leg instead of the built-in's 21 km, so that the test takes seconds)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import auvplan
from auvplan import cli
from auvplan.app.bench.members import member_label, parse_label
from auvplan.app.bench.sweep import SweepSpec, run_chunk
from auvplan.errors import AuvplanError

DATA = Path(auvplan.__file__).parent / "data"
ARCTIC = f'{{ file = "{DATA}/arctic20km_lofoten_cut.nc", name = "arctic20km" }}'
NORDIC = f'{{ file = "{DATA}/nordic4km_lofoten_cut.nc", name = "nordic4km" }}'


def _perturbed(seed: int) -> str:
    return f"{{ perturbation = {{ count = 2, spread_mps = 0.1, correlation_m = 5000.0, seed = {seed} }} }}"


def _scenario(path: Path, *members: str) -> Path:
    """lofoten-two-models on a 1.6 km leg, robust = none, with these members."""
    text = (DATA / "scenarios" / "lofoten-two-models.toml").read_text()
    head, _, rest = text.partition("members = [")
    text = head + f"members = [{', '.join(members)}]\n" + rest.partition("]\n")[2]
    path.write_text(text.replace('"../', f'"{DATA}/')
                    .replace("goal = [11200.0, -8600.0, -50.0]", "goal = [12600.0, 11300.0, -50.0]")
                    .replace('robust = "p90"', 'robust = "none"'))
    return path


def _direct(path: Path, capsys) -> dict:
    capsys.readouterr()
    assert cli.main(["plan", str(path), "--json", "--seed", "0"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert len(rec["members"]) == 1
    return rec["members"][0]


def test_bench_over_members_gives_one_row_per_member_equal_to_a_direct_plan(tmp_path, capsys):
    toml = _scenario(tmp_path / "lofoten-short.toml", ARCTIC, NORDIC, _perturbed(3))
    spec = SweepSpec((str(toml),), seeds=1, members=("arctic20km", "nordic4km"), chunk=1)
    tasks = spec.tasks()
    assert [t[0] for t in tasks] == [f"{toml}@arctic20km", f"{toml}@nordic4km"]  # one cell per member
    rows = [r for t in tasks for r in run_chunk(t, spec)]
    assert [r["member"] for r in rows] == ["arctic20km", "nordic4km"]
    for r, member in zip(rows, (ARCTIC, NORDIC), strict=True):
        direct = _direct(_scenario(tmp_path / f"{r['member']}.toml", member), capsys)  # that member alone
        assert direct["name"] == r["member"]
        assert r["arrival_s"] == pytest.approx(direct["arrival_s"], abs=1e-5)  # rows round to 1e-6
        assert r["member_energy_wh"] == pytest.approx(direct["energy_wh"], abs=1e-5)
        assert r["member_success"] is direct["success"] is True
        assert r["status"] == "EXACT"
        # the closed-loop flight of the row is in that member too: within 2 % of the budget's flight in it
        assert r["sim_duration_s"] == pytest.approx(r["arrival_s"], rel=0.02)
    assert rows[1]["arrival_s"] > 1.2 * rows[0]["arrival_s"]  # against the coastal current in Nordic-4km


def _perturbed_scenario(path: Path, seed: int, members: bool = True) -> Path:
    """A flat 1 km box, a uniform current and two perturbed members, a fixed 583 m route (fast to fly)."""
    entry = ("members = [ { perturbation = { count = 2, spread_mps = 0.15, correlation_m = 500.0, "
             f"seed = {seed} }} }} ]")
    path.write_text(f"""
name = "perturbed-pair"
[bounds]
x = [0.0, 1000.0]
y = [0.0, 1000.0]
z = [-200.0, 0.0]
[terrain.synthetic]
kind = "flat"
depth = 200.0
cell_m = 100.0
[currents]
uniform = [0.2, 0.1, 0.0]
{entry if members else ""}
[mission]
start = [200.0, 200.0, -50.0]
goal = [700.0, 500.0, -50.0]
route = [[200.0, 200.0, -50.0], [700.0, 500.0, -50.0]]
[vehicle]
speed = 1.0
""")
    return path


def test_perturbation_seeds_are_an_axis_equal_to_editing_the_seed(tmp_path):
    toml = _perturbed_scenario(tmp_path / "pair.toml", 3)
    spec = SweepSpec((str(toml),), seeds=1, members=("perturbed1",), member_seeds=(3, 8))
    tasks = spec.tasks()
    assert [t[0] for t in tasks] == [f"{toml}@perturbed1~3", f"{toml}@perturbed1~8"]
    rows = [run_chunk(t, spec)[0] for t in tasks]
    assert [(r["member"], r["member_seed"]) for r in rows] == [("perturbed1", 3), ("perturbed1", 8)]
    assert rows[0]["arrival_s"] != rows[1]["arrival_s"]  # another draw of the perturbation
    for seed, row in ((3, rows[0]), (8, rows[1])):  # == the seed written in the file
        edited = SweepSpec((str(_perturbed_scenario(tmp_path / f"s{seed}.toml", seed)),), seeds=1,
                           members=("perturbed1",))
        again = run_chunk(edited.tasks()[0], edited)[0]
        for k in ("arrival_s", "member_energy_wh", "member_success", "cost", "sim_duration_s"):
            assert again[k] == row[k], k
        assert again["member_seed"] == ""  # the scenario's own seed


def test_labels_round_trip_and_bad_members_are_refused(tmp_path, capsys):
    for s, m, seed in (("a.toml", None, None), ("a.toml", "nordic4km", None), ("dir@x/a.toml", "perturbed2", 7),
                       ("lofoten-two-models", "ens[3]", None)):
        assert parse_label(member_label(s, m, seed)) == (s, m, seed)
    pair = str(_perturbed_scenario(tmp_path / "pair.toml", 3))
    assert [t[0] for t in SweepSpec((pair,), members=("each", "scenario")).tasks()] == [
        f"{pair}@perturbed0", f"{pair}@perturbed1", pair]
    with pytest.raises(AuvplanError, match="no such member; it has perturbed0, perturbed1"):
        SweepSpec((pair,), members=("hycom",)).tasks()
    with pytest.raises(AuvplanError, match="has no \\[currents\\] members"):
        SweepSpec((str(_perturbed_scenario(tmp_path / "none.toml", 3, members=False)),), members=("each",)).tasks()
    assert cli.main(["bench", "--scenarios", pair, "--members", "hycom", "--out",
                     str(tmp_path / "b"), "--workers", "1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--members 'hycom': no such member" in err[0]
