"""The scenario JSON Schema and template (issue #17 item 4): generated from the loader's tables,
valid JSON Schema, never stricter than the loader, every built-in and the template validate;
the README's scenario sketch parses."""

from __future__ import annotations

import dataclasses
import json
import re
import tomllib
from pathlib import Path

import jsonschema
import pytest
from hypothesis import HealthCheck, given, settings

from auvplan import cli
from auvplan.errors import AuvplanError
from auvplan.io.scenario import loader as sc
from auvplan.io.scenario import validate
from auvplan.io.scenario.schema import SCHEMA_VERSION, field_docs, scenario_schema, template
from scenario_mutations import BUILTINS, documents

README = Path(__file__).parents[2] / "README.md"


@pytest.fixture(scope="module")
def validator():
    schema = scenario_schema()
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


def test_schema_is_versioned_and_covers_every_key_of_every_table():
    schema = scenario_schema()
    assert schema["x-auvplan-schema-version"] == SCHEMA_VERSION and SCHEMA_VERSION in schema["$id"]
    props = schema["properties"]
    assert set(props) == validate._TOP_KEYS
    for key, cls in validate.SECTIONS.items():
        table = props[key]["anyOf"][0] if key == "terrain" else props[key]
        fields = {f.name for f in dataclasses.fields(cls) if f.init and not f.name.startswith("_")}
        fields |= {"preset"} if key == "vehicle" else set()  # read before the table: the preset's figures (#51)
        assert set(table["properties"]) == fields, key
        assert table["additionalProperties"] is False


@pytest.mark.parametrize("name", sorted(BUILTINS))
def test_every_builtin_validates_against_the_schema(validator, name):
    assert not list(validator.iter_errors(BUILTINS[name]))


def test_the_schema_catches_types_and_unknown_keys(validator):
    doc = json.loads(json.dumps(BUILTINS["marcus-wake"]))
    doc["planner"]["population"] = "50"
    doc["mission"]["strat"] = [0.0, 0.0, 0.0]
    messages = [e.message for e in validator.iter_errors(doc)]
    assert any("'50' is not of type 'integer'" in m for m in messages)
    assert any("strat" in m for m in messages)


@settings(max_examples=300, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(documents(max_mutations=2))
def test_the_schema_is_never_stricter_than_the_loader(validator, case):
    _, doc, _ = case
    try:
        sc.from_dict(doc, "generated.toml")
    except AuvplanError:
        return
    errors = [e.message for e in validator.iter_errors(doc)]
    assert not errors, errors


def test_template_validates_builds_and_documents_keys(validator, tmp_path):
    text = template("survey")
    doc = tomllib.loads(text)
    assert not list(validator.iter_errors(doc))
    world, mission = sc.build(sc.loads(text, "survey.toml"))
    assert mission.start != mission.goal and world.terrain is not None
    assert "# Food sources / individuals / particles." in text  # descriptions from the dataclasses
    # every commented key = default line of the parameter tables is itself valid: uncomment them all
    lines = text.splitlines()
    start = next(i for i, ln in enumerate(lines) if ln == "[vehicle]")
    live = lines[:start] + [re.sub(r"^# (\[?[a-z_.]+\]?( = .*)?)$", r"\1", ln) if "(no limit" not in ln else ln
                            for ln in lines[start:]]
    uncommented = "\n".join(live)
    assert uncommented.count("\n# ") < text.count("\n# ")
    sc.build(sc.loads(uncommented, "all-defaults.toml"))


def test_field_docs_reads_numpydoc_attributes():
    docs = field_docs(validate.SECTIONS["planner"])
    assert docs["population"] == "Food sources / individuals / particles."
    assert docs["w_terrain"] == docs["w_length"]  # "w_length, w_terrain, w_energy : float"


def test_readme_scenario_sketch_parses():
    blocks = re.findall(r"```toml\n(.*?)```", README.read_text(), re.S)
    assert blocks, "the README has no TOML scenario sketch"
    for block in blocks:
        s = sc.loads(block, "README.md")
        assert s.mission.goal and s.planner.name


def test_cli_scenario_commands(tmp_path, capsys):
    assert cli.main(["scenario", "schema"]) == 0
    assert json.loads(capsys.readouterr().out) == json.loads(json.dumps(scenario_schema()))
    path = tmp_path / "new.toml"
    assert cli.main(["scenario", "new", str(path)]) == 0
    assert cli.main(["validate", str(path)]) == 0
    path.write_text("# my edits\n" + path.read_text())
    capsys.readouterr()
    assert cli.main(["scenario", "new", str(path)]) == 2
    assert "exists" in capsys.readouterr().err and path.read_text().startswith("# my edits")
    assert not (tmp_path / ".auvplan-manifest.json").exists()
