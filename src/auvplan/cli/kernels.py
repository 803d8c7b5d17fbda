"""``auvplan kernels build``: compile the kernels ahead of time, so that commands start without numba (issue 56)."""

from __future__ import annotations

import argparse
import contextlib
import io
import sys

__all__ = ["cmd_kernels_build"]


def cmd_kernels_build(args: argparse.Namespace) -> int:
    """``kernels build [SCENARIO ...]``: plan each SCENARIO (its kernels compiled into numba's cache), then compile
    every kernel signature numba's cache holds for the current sources into one extension module
    (:mod:`auvplan.runtime.aotbuild`).  A build that cannot be done is one line on stderr and exit 1: the kernels
    then run through numba, as before."""
    from ..runtime.aotbuild import BuildError, build
    from .parser import main

    for name in args.scenarios:
        with contextlib.redirect_stdout(io.StringIO()):
            code = main(["-q", "plan", name, "--json"])
        if code == 2:  # its one line is on stderr already
            return 2
    try:
        built = build()
    except BuildError as exc:
        print(f"auvplan: kernels not compiled ahead of time ({exc}); they run through numba as before",
              file=sys.stderr)
        return 1
    done = "up to date" if built.seconds == 0 else f"built in {built.seconds:.0f} s"
    print(f"kernels: {built.signatures} signatures of {built.kernels} kernels in {built.path} ({done}); "
          f"{built.skipped} left to numba (types it binds at run time)" if built.skipped else
          f"kernels: {built.signatures} signatures of {built.kernels} kernels in {built.path} ({done})")
    return 0
