"""The jobs the command line and the planning page both run: plan, run, survey, sweep, ensemble, and the one
writer of a results folder."""

__all__: list[str] = []
