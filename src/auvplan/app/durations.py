"""Durations and departure offsets as the command line writes them ('15min', '+6h'): parsed without the
sweep's machinery, so that ``plan``'s parser, which checks ``--step``'s default on every call, imports no
more than this (issue 56)."""

from __future__ import annotations

from ..errors import AuvplanError

__all__ = ["parse_duration", "is_offset"]


def parse_duration(text: str, what: str) -> float:
    """Seconds of '15min', '900s', '2h', '1.5h' or a bare number of seconds.

    Parameters
    ----------
    text : str
        The duration.
    what : str
        The option it came from, for the message.

    Returns
    -------
    float
        Seconds.
    """
    units = {"s": 1.0, "sec": 1.0, "min": 60.0, "m": 60.0, "h": 3600.0, "d": 86400.0}
    t = text.strip().lower().lstrip("+")
    for unit in sorted(units, key=len, reverse=True):
        if t.endswith(unit):
            t, scale = t[: -len(unit)], units[unit]
            break
    else:
        scale = 1.0
    try:
        return float(t) * scale
    except ValueError:
        raise AuvplanError(f"{what} {text!r}: not a duration (e.g. 15min, 900s, 2h)") from None


def is_offset(text: str) -> bool:
    """Whether a departure is an offset after start_time ('+6h', '900') rather than a date-time.

    Parameters
    ----------
    text : str
        The departure.

    Returns
    -------
    bool
        True for an offset.
    """
    return text.startswith("+") or text[:1].isdigit() and not any(c in text for c in "-:T")
