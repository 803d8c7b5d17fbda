"""The command line's durations and departure offsets (``app.durations``: ``plan --step``, ``--depart-between``)
worked by hand: every unit's factor, the sign and blanks a user types, and which departures are offsets."""

from __future__ import annotations

import pytest

from auvplan.app.durations import is_offset, parse_duration
from auvplan.errors import AuvplanError


@pytest.mark.parametrize(("text", "seconds"), [
    ("900", 900.0), ("2.5", 2.5), ("7s", 7.0), ("7sec", 7.0), ("15min", 900.0), ("3m", 180.0), ("2h", 7200.0),
    ("1.5h", 5400.0), ("2d", 172800.0), ("+6h", 21600.0), (" 15MIN ", 900.0), ("+0h", 0.0), ("0.25d", 21600.0),
])
def test_each_unit_s_seconds_by_hand(text, seconds):
    """Each unit's factor (s and sec 1, min and m 60, h 3600, d 86400), a bare number in seconds, a leading '+'
    and blanks dropped, upper case read as lower."""
    assert parse_duration(text, "--step") == seconds


@pytest.mark.parametrize("text", ["fast", "15 minutes", "h", "", "1:30"])
def test_a_duration_that_is_not_one_names_the_option_and_the_text(text):
    with pytest.raises(AuvplanError, match=rf"^--step {text!r}: not a duration \(e\.g\. 15min, 900s, 2h\)$"):
        parse_duration(text, "--step")


@pytest.mark.parametrize(("text", "offset"), [
    ("+6h", True), ("900", True), ("6h", True), ("+0h", True), ("1.5d", True),
    ("2026-12-06", False), ("2026-12-06T12:00", False), ("12:00", False), ("1T", False), ("now", False),
    ("-15min", False), ("", False),
])
def test_which_departures_are_offsets_by_hand(text, offset):
    """An offset after start_time starts with '+' or a digit and holds none of a date-time's '-', ':' or 'T'."""
    assert is_offset(text) is offset
