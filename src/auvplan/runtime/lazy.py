"""Names of a package loaded on first access (PEP 562), so that importing the package stays cheap (issue 56)."""

from __future__ import annotations

import importlib
import sys
import types
from collections.abc import Callable, Iterable, Mapping
from typing import Any

__all__ = ["lazy_attributes"]


def lazy_attributes(package: str, names: Mapping[str, str],
                    exported: Iterable[str]) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """A package's module-level ``__getattr__`` and ``__dir__`` for names loaded on first access.

    Parameters
    ----------
    package : str
        The package's ``__name__``; a name is kept in its namespace once loaded.
    names : Mapping[str, str]
        Each lazily loaded name and the module that defines it.
    exported : Iterable[str]
        The package's ``__all__``, listed by ``dir()`` before they are loaded.

    Returns
    -------
    tuple of callable
        ``(__getattr__, __dir__)``: an unknown name raises :class:`AttributeError` naming the package.
    """
    namespace = sys.modules[package].__dict__
    listed = set(exported)

    def getattr_(name: str) -> Any:
        module = names.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module), name)
        namespace[name] = value
        for other, where in names.items():  # a submodule named like a name it exports (``endurance.assess``):
            if isinstance(namespace.get(other), types.ModuleType) and where in sys.modules:  # importing it
                namespace[other] = getattr(sys.modules[where], other)  # bound the module: the name, as eagerly
        return value

    def dir_() -> list[str]:
        return sorted(set(namespace) | listed)

    return getattr_, dir_
