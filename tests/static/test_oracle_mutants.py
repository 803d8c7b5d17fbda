"""The catalogue of planted bugs (``tools/oracle_mutants.py``, ``make oracle-mutants``) stays plantable: every
mutant's original text occurs exactly once in its file, so a move or an edit of the code it targets shows here
instead of when the catalogue is next run (five had gone stale: the code had moved or been reworded)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location("oracle_mutants", ROOT / "tools" / "oracle_mutants.py")
assert _spec is not None and _spec.loader is not None
_mod = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_mod)


@pytest.mark.parametrize("name", sorted(_mod.MUTANTS))
def test_every_mutant_names_text_found_once_in_its_file(name: str) -> None:
    path, original, mutated = _mod.MUTANTS[name]
    text = (ROOT / "src" / "auvplan" / path).read_text(encoding="utf-8")
    assert text.count(original) == 1, f"{name}: its original text occurs {text.count(original)} times in {path}"
    assert mutated != original


def test_the_equivalent_list_names_catalogued_mutants() -> None:
    assert set(_mod.EQUIVALENT) <= set(_mod.MUTANTS)
