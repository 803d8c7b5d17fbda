"""The package's version, importable from anywhere without the package root (``io.scenario.schema``)."""

__all__ = ["__version__"]

__version__ = "0.1.0"
