"""The time-optimal planner: earliest-arrival search in a time-varying current."""

__all__: list[str] = []
