"""Generic partitioned coupling: schemes, accelerations, convergence measures.

Knows neither fluid nor structure: participants are seen through
:class:`coupling.participant.Participant` and exchange named flat float64 vectors.
"""
from .acceleration import ACCELERATIONS, AccelerationSettings, register_acceleration
from .convergence import ConvergenceMeasure
from .participant import Participant
from .scheme import (EXTRAPOLATION_WEIGHTS, ON_MAX_ITERATIONS, SCHEMES, SPLIT_UNCONVERGED,
                     CouplingError, CouplingLog, CouplingSettings, Loop, WindowLog, advance,
                     register_scheme, run, start)

__all__ = ["ACCELERATIONS", "AccelerationSettings", "register_acceleration",
           "ConvergenceMeasure", "Participant", "EXTRAPOLATION_WEIGHTS", "ON_MAX_ITERATIONS",
           "SCHEMES", "SPLIT_UNCONVERGED", "CouplingError", "CouplingLog", "CouplingSettings",
           "WindowLog", "register_scheme", "run", "start", "advance", "Loop"]
