"""Figures: static matplotlib plots (``plots``) and the offline plotly report (``report``).

The interactive views (``report``, ``chart``, ``scene3d``) need plotly, an optional dependency
(``pip install 'auvplan[report]'``); the static figures need only matplotlib.
"""

from __future__ import annotations

__all__ = ["PLOTLY_MISSING", "MissingPlotly"]

PLOTLY_MISSING = "the HTML report needs plotly, which is not installed: pip install 'auvplan[report]'"
"""The one line said when plotly is missing (as :func:`auvplan.errors.require` says it)."""


class MissingPlotly:
    """Stand-in for a plotly module that is not installed: any use raises ``ImportError(PLOTLY_MISSING)``.

    Lets a module that also holds plotly-free helpers (``scene3d``'s geometry, used by the static
    figures) be imported without plotly.
    """

    def __getattr__(self, name: str) -> object:
        raise ImportError(PLOTLY_MISSING)
