"""Where a survey's lines go: the line frame (:mod:`.frame`), the sensor's swath (:mod:`.swath`), depth-adaptive
placement with guaranteed overlap (:mod:`.placement`, the lines as data :mod:`.lineset`, its envelopes
:mod:`.envelope`, its spacing under navigation error :mod:`.navspacing`) and corridor lines along a centre line
(:mod:`.corridor`)."""

from .placement import LineParams, SurveyLine, SurveyLines, place_lines

__all__ = ["LineParams", "SurveyLine", "SurveyLines", "place_lines"]
