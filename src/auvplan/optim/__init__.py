"""Generic population optimisers (know nothing of paths): ABC, IABC, GA, PSO."""

from .base import Optimizer, OptimizeResult, Termination, minimize
from .bee import ABC, IABC, ABCParams, IABCParams
from .ga import GA, GAParams
from .pso import PSO, PSOParams

__all__ = [
    "ABC",
    "ABCParams",
    "GA",
    "GAParams",
    "IABC",
    "IABCParams",
    "OptimizeResult",
    "Optimizer",
    "PSO",
    "PSOParams",
    "Termination",
    "minimize",
]
