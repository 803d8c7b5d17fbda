"""mutants20: ``io/missions/parsed.py``'s memo (docs/mutants.md section 7).  Oracles: identity and call counts —
outside :func:`parse_once` nothing is kept; inside, one document at a time (a new text drops what was derived from
the last), an equal text is the same document, an exception is raised at every call, and a nested block has its own
memo and gives the outer one back."""

from __future__ import annotations

import pytest

from auvplan.io.missions import parsed


def test_outside_the_block_every_call_computes():
    calls = []
    assert parsed.loads('{"v": 1}') is not parsed.loads('{"v": 1}')
    for _ in range(2):
        parsed.remembered("k", None, lambda: calls.append(1))
    assert len(calls) == 2


def test_one_document_at_a_time_and_an_equal_text_is_the_same_document():
    t1 = '{"v": 1}'
    with parsed.parse_once():
        a = parsed.loads(t1)
        assert parsed.loads("".join(['{"v"', ": 1}"])) is a  # equal, not the same str object
        assert parsed.remembered("k", a, lambda: "first") == "first"
        assert parsed.remembered("k", {"v": 1}, lambda: "other doc") == "other doc"  # kept by identity
        parsed.loads('{"v": 2}')  # another text: the memo is cleared
        assert parsed.remembered("k", a, lambda: "again") == "again"
        assert parsed.loads(t1) is not a


def test_an_exception_is_raised_at_every_call_and_never_kept():
    def boom():
        raise ValueError("no")

    with parsed.parse_once():
        doc = parsed.loads("[1]")
        for _ in range(2):
            with pytest.raises(ValueError):
                parsed.remembered("k", doc, boom)
        assert parsed.remembered("k", doc, lambda: 7) == 7 and parsed.remembered("k", doc, lambda: 8) == 7


def test_a_nested_block_has_its_own_memo_and_gives_the_outer_one_back():
    with parsed.parse_once():
        a = parsed.loads("[1]")
        with parsed.parse_once():
            assert parsed.loads("[1]") is not a
        assert parsed.loads("[1]") is a
    assert parsed.loads("[1]") is not a
