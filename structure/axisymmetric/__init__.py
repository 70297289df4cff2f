"""The diaphragm as a shell of revolution (as BOSOR4, Bushnell 1974, treats shells of
revolution): the axisymmetric state along the meridian, found by Newton's method on the exact
Hessian of the total potential.

The meridian runs in its rest arc length S from the pole (on the axis) to the rim; r(S) and
z(S) are cubic Hermite interpolants, C1, of nodal values and slopes
(:mod:`.hermite`, :mod:`.meridian`); the pole is held on the axis with a horizontal tangent, the
rim clamped, simply supported or on a mirror plane (:mod:`.supports`). The strains are the
large-rotation axisymmetric shell's (:mod:`.kinematics`), the laws the 3-D sheet's at the
meridian's principal stretches, with the tension field and the Kirchhoff-Love bending energy
(:mod:`.laws`); the loads a uniform pressure, the liquid below the sheet and the sheet's own
weight, each by its potential (:mod:`.loads`). :mod:`.energy` assembles the potential, its
gradient and its sparse Hessian; :mod:`.solve` finds equilibria under a held pressure or a
held volume (bordered Newton); :mod:`.fields` reads the stretches, resultants, stresses and
moments off a state. The tank wall is a smooth barrier (:mod:`.wall`); :mod:`.continuation`
follows the equilibria by pseudo-arc-length in the liquid's volume through its limit points,
and :mod:`.fill_drain` fills and drains the tank, snapping where a leg meets one.
:mod:`.harmonics` gives the second variation for each circumferential wave number n (as
BOSOR4 does), and :mod:`.folding` the stability table of a leg and the onset of folding with
its number of lobes.
"""
from .continuation import ContinuationSettings, EquilibriumCurve, trace
from .fields import meridian_fields
from .fill_drain import Leg, leg
from .folding import Onset, onset_of_folding, stability_table
from .harmonics import HarmonicStability, stability
from .laws import law_of
from .loads import AxisymmetricLoad
from .meridian import RestShape, build_meridian
from .model import ShellOfRevolution, shell_of_revolution
from .solve import AxisymmetricEquilibrium, NewtonSettings, equilibrium, path
from .wall import BarrierWall, barrier_wall

__all__ = ["AxisymmetricEquilibrium", "AxisymmetricLoad", "BarrierWall", "ContinuationSettings",
           "EquilibriumCurve", "HarmonicStability", "Leg", "Onset", "NewtonSettings",
           "RestShape", "ShellOfRevolution",
           "barrier_wall", "build_meridian", "equilibrium", "law_of", "leg", "meridian_fields",
           "onset_of_folding", "path", "shell_of_revolution", "stability", "stability_table",
           "trace"]
