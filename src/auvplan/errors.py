"""Exception hierarchy of auvplan.

Invalid *input* raises one of these; a planner or simulation that cannot reach
its goal returns a result with a :class:`~auvplan._types.Status` instead.
"""

__all__ = ["AuvplanError", "ScenarioError", "DataError"]


class AuvplanError(Exception):
    """Root of every error auvplan raises on purpose."""


class ScenarioError(AuvplanError, ValueError):
    """A scenario file or scenario value is malformed (names the file, key and value)."""


class DataError(AuvplanError, ValueError):
    """Gridded input data (bathymetry, currents) is unusable (names the file and variable)."""
