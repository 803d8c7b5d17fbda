"""Coverage surveys over bathymetry (issue 37): depth-adaptive lines with guaranteed overlap
(:mod:`~auvplan.survey.lines`, the swath model in :mod:`~auvplan.survey.lines.swath`), turns the vehicle can
fly (:mod:`~auvplan.survey.turns`), the whole mission with its transits (:mod:`~auvplan.survey.mission`)
and the coverage measured on a track (:mod:`~auvplan.survey.coverage`).
"""

from __future__ import annotations

from .lines.placement import LineParams, SurveyLine, SurveyLines, place_lines
from .lines.swath import Sensor, swath_reach

__all__ = ["Sensor", "swath_reach", "LineParams", "SurveyLine", "SurveyLines", "place_lines"]
