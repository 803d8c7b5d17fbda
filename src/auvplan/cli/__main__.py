"""``python -m auvplan.cli``: the command line."""

from .parser import main_entry

main_entry()
