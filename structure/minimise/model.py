"""The potential that the minimisation statics minimise, built from a membrane model's
energies: the in-plane law (the full law, or the tension field with a residual stiffness),
the calibrated bending, the tank wall as a barrier (:mod:`structure.minimise.barrier`) and
the hydrostatic load's potential (the energy form of :mod:`structure.newton.system`),

    Pi(x) = W_membrane + W_bending + B_wall - rho b . M1 - sum_i m_i b . x_i,

minimised under V(x) = V* with the pressure level the volume's multiplier.

**The tension field's residual stiffness.** The relaxed energy has no stiffness against
compression, so a slack region is held by bending alone and Newton's tangent is nearly
singular there; a small fraction e of the full law is kept beside it (as explicit fabric
laws keep a residual compressive stiffness),

    W = (1 - e) W_tension_field + e W_full,

two membrane terms on the same triangles.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..newton.system import NewtonModel
from ..tangent.bending import BendingTerm
from ..tangent.membrane import MembraneTerm
from .barrier import REST_FRACTION, BarrierWall

DHAT = 1e-3
"""The wall barrier's default activation gap (m)."""
RESIDUAL_STIFFNESS = 1e-2
"""The tension field's default residual stiffness e (-)."""


def membrane_terms(xpbd_model, residual_stiffness: float = RESIDUAL_STIFFNESS,
                   tension_field: bool | None = None) -> list:
    """The in-plane terms of a :class:`structure.xpbd.model.XpbdModel`: its block law, or,
    where its material wrinkles by the tension field (or ``tension_field`` is True, whatever
    the material says), the relaxed law with ``residual_stiffness`` e in [0, 1) of the block
    law beside it (module doc)."""
    term = MembraneTerm.from_xpbd(xpbd_model)
    if tension_field is not None:
        term = replace(term, law="tension-field" if tension_field else "block")
    if term.law != "tension-field":
        return [term]
    e = float(residual_stiffness)
    if not 0.0 <= e < 1.0:
        raise ValueError(f"residual_stiffness must be in [0, 1), got {residual_stiffness!r}")
    terms = [_scaled(term, 1.0 - e)]
    if e > 0:
        terms.append(_scaled(replace(term, law="block"), e))
    return terms


def _scaled(term: MembraneTerm, factor: float) -> MembraneTerm:
    """The block laws' energy times ``factor`` (stiffness times, compliance over it)."""
    if factor == 1.0:
        return term
    return replace(term, stiffness=term.stiffness * factor, alpha00=term.alpha00 / factor)


def minimisation_model(base, terms, pressure: float,
                       dhat: float = DHAT) -> tuple[NewtonModel, BarrierWall]:
    """(The energy-form model of the potential, its wall barrier) on the grid of ``base`` (a
    :class:`structure.model.MembraneModel`) with the internal-energy ``terms`` (membrane,
    bending) and the tank wall as a barrier whose stiffness carries ``pressure`` (Pa, e.g.
    rho |b| R) at a tenth of ``dhat`` (m)."""
    area = base.node_mass / (base.material.density * base.material.thickness)
    wall = BarrierWall.build(~base.node_fixed, area, base.radius, dhat, pressure, REST_FRACTION)
    return NewtonModel.build(base, list(terms) + [wall], load_form="energy"), wall


def xpbd_terms(xpbd_model, residual_stiffness: float = RESIDUAL_STIFFNESS,
               bending: bool = True, tension_field: bool | None = None) -> list:
    """The internal-energy terms of a :class:`structure.xpbd.model.XpbdModel`: its membrane
    (:func:`membrane_terms`, ``tension_field`` as there) and, with ``bending``, its
    calibrated bending."""
    terms = membrane_terms(xpbd_model, residual_stiffness, tension_field)
    if bending:
        terms.append(BendingTerm(xpbd_model.bending))
    return terms


def inside(wall: BarrierWall, x: np.ndarray, gap: float | None = None) -> np.ndarray:
    """``x`` (n, 3) m with every barrier node closer to the wall than ``gap`` (m; default a
    tenth of dhat, where the barrier carries its pressure) moved radially in to it: a start
    the barrier accepts (the rest shape's nodes lie on the wall)."""
    gap = REST_FRACTION * wall.dhat if gap is None else float(gap)
    x = np.array(x, dtype=float)
    r = np.linalg.norm(x, axis=1)
    move = (wall.weight > 0) & (r > wall.radius - gap)
    x[move] *= ((wall.radius - gap) / r[move])[:, None]
    return x


def projectable(model: NewtonModel) -> tuple:
    """The indices of ``model.terms`` whose element Hessians may be projected to positive
    semi-definite (the membrane's and the bending's; the barrier's are already)."""
    return tuple(i for i, t in enumerate(model.terms)
                 if isinstance(t, (MembraneTerm, BendingTerm)))
