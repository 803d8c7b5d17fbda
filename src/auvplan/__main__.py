"""``python -m auvplan``: the command line (same as the ``auvplan`` script)."""

from .cli import main_entry

if __name__ == "__main__":
    main_entry()
