"""``auvplan ... > /dev/full``: stdout cannot be written.  The command said ``OSError: [Errno 28] No space left on
device`` without its culprit (and ``--help`` exited 0, silent: argparse ignores the failure); now one line on stderr
names stdout, exit 2, no traceback.  A pipe whose reader went away (``| head``) is not an error of the command:
exit 141, silent, as before."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from auvplan import cli
from auvplan.cli.output import StdoutError, named_stdout

pytestmark = pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full (Linux)")

LINE = "auvplan: error: stdout: cannot write the command's output (No space left on device)\n"


def _into_dev_full(*args: str) -> subprocess.CompletedProcess[str]:
    with open("/dev/full", "w") as full:  # every write fails with ENOSPC
        return subprocess.run([sys.executable, "-m", "auvplan", *args], stdout=full, stderr=subprocess.PIPE,
                              text=True, timeout=120)


@pytest.mark.parametrize("args", [("scenarios",), ("--help",)])
def test_a_full_stdout_is_named_in_one_line_exit_2(args):
    done = _into_dev_full(*args)
    assert (done.returncode, done.stderr) == (2, LINE), done.stderr[-600:]


def test_a_write_that_fails_in_the_middle_of_a_command_is_named(monkeypatch, capsys):
    """In process, deterministic: the stream fails on the command's first write (not at the final flush)."""
    class Full:
        def write(self, text):
            raise OSError(28, "No space left on device")

        def flush(self):
            pass

    monkeypatch.setattr(sys, "stdout", Full())
    assert cli.main(["scenarios"]) == 2
    assert capsys.readouterr().err == LINE


def test_a_broken_pipe_is_not_renamed():
    """``| head``: BrokenPipeError passes through the named stdout unchanged (the command line exits 141)."""
    class Gone:
        def write(self, text):
            raise BrokenPipeError(32, "Broken pipe")

        def flush(self):
            pass

    real = sys.stdout
    sys.stdout = Gone()
    try:
        with pytest.raises(BrokenPipeError), named_stdout():
            print("x")
    finally:
        sys.stdout = real
    assert not issubclass(BrokenPipeError, StdoutError)
