"""Generic population optimisers (know nothing of paths): ABC, IABC, GA, PSO, scipy's DE, and a
pattern search for local refinement."""

from .base import Optimizer, OptimizeResult, Problem, Termination, minimize
from .bee import ABC, IABC, ABCParams, IABCParams
from .de import DEParams, differential_evolution
from .ga import GA, GAParams
from .local import PatternParams, pattern_search
from .pso import PSO, PSOParams

__all__ = [
    "ABC",
    "ABCParams",
    "DEParams",
    "GA",
    "GAParams",
    "IABC",
    "IABCParams",
    "OptimizeResult",
    "Optimizer",
    "PSO",
    "PSOParams",
    "PatternParams",
    "Problem",
    "Termination",
    "differential_evolution",
    "minimize",
    "pattern_search",
]
