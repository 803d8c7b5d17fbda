"""A killed departure sweep resumes from checkpoints keyed on everything its rows depend on: the scenario's text
and, what the first tests never varied, the bytes of the data files it names (a current or tide file
downloaded again under the same name) — issue 49's kind of bug: the fixtures never changed a data file
between the kill and the resume."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from auvplan.io.scenario.builtins import resolve
from auvplan.runtime.parallel import Runner


class _Keys(Exception):
    """Raised by :class:`_Spy` with the checkpoint keys the sweep asked for."""


class _Spy(Runner):
    """A runner that runs nothing: it reports the sweep's checkpoint keys (what a resume would read back)."""

    def map(self, fn, tasks, keys=None, **kw):  # type: ignore[override]
        raise _Keys(list(keys or []))


def _keys(scenario: Path) -> list[str]:
    from auvplan.app.sweep import sweep_scenario

    with pytest.raises(_Keys) as got:
        sweep_scenario(str(scenario), ["+0h", "+1h"], "1h", runner=_Spy())
    return got.value.args[0]


def test_a_tide_file_edited_between_the_kill_and_the_resume_is_another_sweep(tmp_path):
    """``rotary-tide`` with its station file in the scenario's folder.  Oracle: the keys after the file's
    amplitudes were halved are all new (its departures are planned again, not read back from the old tide's
    rows; the same files give the same keys: test_parallel's resumed sweep)."""
    toml = Path(resolve("rotary-tide")).read_text(encoding="utf-8").replace('"../tides_rotary.json"', '"tide.json"')
    scenario = tmp_path / "rotary.toml"
    scenario.write_text(toml, encoding="utf-8")
    tide = tmp_path / "tide.json"
    doc = json.loads((Path(resolve("rotary-tide")).parent.parent / "tides_rotary.json").read_text(encoding="utf-8"))
    tide.write_text(json.dumps(doc), encoding="utf-8")
    first = _keys(scenario)
    assert len(first) == 2
    for station in doc["stations"]:
        station["amplitude_m_s"] = {k: 0.5 * v for k, v in station["amplitude_m_s"].items()}
    tide.write_text(json.dumps(doc), encoding="utf-8")
    assert not set(_keys(scenario)) & set(first)
