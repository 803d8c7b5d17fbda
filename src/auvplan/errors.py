"""Exception hierarchy of auvplan.

Invalid *input* raises one of these; a planner or simulation that cannot reach
its goal returns a result with a :class:`~auvplan._types.Status` instead.
"""

__all__ = ["AuvplanError", "ScenarioError", "DataError", "MissingExtraError", "require"]


class AuvplanError(Exception):
    """Root of every error auvplan raises on purpose."""


class ScenarioError(AuvplanError, ValueError):
    """A scenario file or scenario value is malformed (names the file, key and value)."""


class DataError(AuvplanError, ValueError):
    """Gridded input data (bathymetry, currents) is unusable (names the file and variable)."""


class MissingExtraError(AuvplanError, ImportError):
    """An optional dependency is not installed (names the package and the extra that brings it)."""


def require(module: str, extra: str) -> None:
    """Raise :class:`MissingExtraError` unless ``module`` can be imported.

    Parameters
    ----------
    module : str
        Top-level module name (``"plotly"``, ``"dask"``).
    extra : str
        The ``pip install 'auvplan[extra]'`` that installs it.
    """
    import importlib.util

    if importlib.util.find_spec(module) is None:
        raise MissingExtraError(f"this feature needs {module}, which is not installed: pip install 'auvplan[{extra}]'")
