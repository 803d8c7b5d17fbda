"""Ocean currents: the fields (their interface :mod:`.base`; uniform and Lamb-Oseen vortices :mod:`.fields`, gridded
:mod:`.gridded`), tidal currents (:mod:`.tides`), fields built from fields for ensembles (:mod:`.ensemble`) and the
ground speed of a vehicle holding a line in them (:mod:`.crab`)."""

from .ensemble import MeanCurrent, PerturbedCurrent, ShiftedCurrent
from .fields import CurrentField, GriddedCurrent, LambOseenVortices, UniformCurrent
from .tides import HarmonicTables, TidalCurrent

__all__ = ["CurrentField", "UniformCurrent", "LambOseenVortices", "GriddedCurrent", "HarmonicTables",
           "TidalCurrent", "PerturbedCurrent", "MeanCurrent", "ShiftedCurrent"]
