"""The command line (DESIGN.md §4): argument parsing and printing only, one module per command group.

:mod:`.parser` declares every command's arguments and maps errors to exit codes; the handlers, one module per
command group, read the arguments, call the jobs of :mod:`auvplan.app` (and the library) and print.  The
console script is ``auvplan.cli:main_entry``; importing this package imports nothing of the numerical layers.
"""

from __future__ import annotations

from .parser import _parser as _parser  # the parser itself (tests, the docs tools)
from .parser import main, main_entry

__all__ = ["main", "main_entry"]
