"""Coverage surveys over bathymetry (issue 37): depth-adaptive lines with guaranteed overlap
(:mod:`~auvplan.survey.lines`, the swath model in :mod:`~auvplan.survey.lines.swath`), turns the vehicle can
fly (:mod:`~auvplan.survey.turns`), the whole mission with its transits (:mod:`~auvplan.survey.mission`)
and the coverage measured on a track (:mod:`~auvplan.survey.coverage`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..runtime.lazy import lazy_attributes

if TYPE_CHECKING:  # pragma: no cover - for type checkers only
    from .lines.placement import LineParams, SurveyLine, SurveyLines, place_lines
    from .lines.swath import Sensor, swath_reach

__all__ = ["Sensor", "swath_reach", "LineParams", "SurveyLine", "SurveyLines", "place_lines"]

_LAZY = {
    **{name: "auvplan.survey.lines.placement" for name in ("LineParams", "SurveyLine", "SurveyLines", "place_lines")},
    **{name: "auvplan.survey.lines.swath" for name in ("Sensor", "swath_reach")},
}
"""Loaded on first access: a scenario's ``[survey]`` table places no line (issue 56)."""

__getattr__, __dir__ = lazy_attributes(__name__, _LAZY, __all__)
