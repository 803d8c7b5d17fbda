"""Scenario files: the TOML tables, their checks and schema, and the World and Mission they build."""

__all__: list[str] = []
