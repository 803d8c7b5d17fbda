"""Issue 56, never silent: the live line (auvplan.cli.output._Live) counts stderr's silence from the last line
any live line or stage drew, so a stage that follows another is drawn QUIET_S after the last line, not
QUIET_S after its own start (which added the silence before it: 1.5-1.9 s at stage changes under load).
The clock is a fake one set by hand: no timing."""

from __future__ import annotations

import io
import threading

from tqdm import tqdm

from auvplan.cli.output import QUIET_S, _Live


def _clock(buf: io.StringIO, text: str, now: list[float], delay: float = QUIET_S) -> tqdm:
    """A stage clock as the command line makes it, created at ``now[0]`` on a clock of the test's."""
    bar = tqdm(total=None, desc=text, bar_format="{desc}", file=buf, leave=False, delay=delay)
    bar._time = lambda: now[0]
    bar.start_t = bar.last_print_t = now[0]
    return bar


def test_a_stage_after_another_is_drawn_once_stderr_was_quiet_for_quiet_s_in_all():
    buf, now = io.StringIO(), [1000.0]
    live = _Live()
    live.thread = threading.current_thread()  # as if its thread ran: the test ticks by hand
    first = _clock(buf, "reading", now)
    live.show(first)
    now[0] += 0.5 * QUIET_S
    assert not live.tick() and "reading" not in buf.getvalue()  # the first stage keeps its own delay
    now[0] = 1000.0 + 1.1 * QUIET_S
    assert live.tick() and "reading" in buf.getvalue()  # drawn at 1000 + 1.1 QUIET_S
    now[0] = 1000.0 + 1.3 * QUIET_S
    first.close()  # the stage ends (as Progress.stage ends its clock) ...
    second = _clock(buf, "writing", now)  # ... and the next begins, 0.2 QUIET_S after the last line
    live.show(second)
    now[0] = 1000.0 + 1.8 * QUIET_S  # quiet for 0.7 QUIET_S: not yet
    assert not live.tick() and "writing" not in buf.getvalue()
    now[0] = 1000.0 + 2.2 * QUIET_S  # quiet for 1.1 QUIET_S in all, 0.9 of them the new stage's
    assert live.tick() and "writing" in buf.getvalue()
    assert not live.tick()  # just drawn
    now[0] += 2.0 * QUIET_S
    live.drawn = now[0] - 0.5 * QUIET_S  # a stage line written since (LIVE.said): quiet from then
    assert not live.tick()
    live.thread = None
    drawn = buf.getvalue()
    live.end()
    assert buf.getvalue()[len(drawn):].strip() == ""  # drawn within its delay, cleared all the same
    assert buf.getvalue() != drawn


def test_a_stage_without_a_reporter_replaces_the_live_line(capsys):
    """``survey``'s stages: the line, then the stage's clock in place of the one before (which used to stay
    live, the stage's text written onto its line)."""
    from auvplan.cli import output

    output.starting("survey: starting")
    first = output.LIVE.display
    output.stage("planning and flying the survey")
    assert first.disable and output.LIVE.display.desc == "planning and flying the survey"  # the first closed
    output.finish()
    assert output.LIVE.display is None
    assert "auvplan: planning and flying the survey …\n" in capsys.readouterr().err


def test_a_quiet_command_s_disabled_bars_pass_through():
    """``-q``/``--json``: the bars are disabled (no ``start_t``): shown, ticked and ended without a word."""
    live = _Live()
    live.show(tqdm(total=3, disable=True))
    assert not live.tick() and live.thread is None
    live.end()
    assert live.display is None and live.drawn == 0.0
