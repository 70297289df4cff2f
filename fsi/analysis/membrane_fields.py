"""Stress, strain and topology of every membrane frame a run recorded, from the run's own law.

Each structure model a run can use has a :class:`FieldRule` in :data:`FIELD_RULES` (filled by
:func:`field_rule`): the membrane term (its triangles, and for a compressible law the energy
that gives the stresses), the incompressible law that gives them for rubber
(:func:`structure.stress.sheet_fields`), the bending model and whether the tension field
marks wrinkles. :func:`frame_fields` gives, per frame, the
per-triangle fields (stored as float32, the units in :data:`fsi.io.output.UNITS`) and the
topology series of :mod:`structure.topology`:

- ``fold_count``: the folds, clusters of triangles on the tension field's wrinkled branch or
  creased (:func:`structure.topology.creased`), over triangles with a free node;
- ``inverted_area_fraction`` and ``inversion_front_deg``;
- ``wall_contact_area`` (m^2) and ``self_contact_nodes``.

Models (the structure model names of :mod:`fsi.setup.models`):

- ``xpbd``: the XPBD blocks (relaxed by the tension field where the material says so) with
  the model's midedge bending;
- ``shell``: the shell's law (Saint Venant-Kirchhoff or neo-Hookean) and bending;
- ``thesis``: the particle membrane's in-plane springs are strain limits (App. G), not a law,
  so its stresses are a law's at its strains, with the midedge bending of the same D.

A sheet whose Poisson ratio is at or above
:data:`structure.stress.INCOMPRESSIBLE_POISSON_RATIO` (rubber: every bundled scene) reports
under every model the stresses of the incompressible neo-Hookean law of its E at its
stretches (relaxed by the tension field where the model has one), not Saint Venant-Kirchhoff's,
whose plane-stress thickness vanishes at large strain; a compressible sheet those of its run's
law (the thesis membrane: Saint Venant-Kirchhoff of its E and nu). ``stress_law`` in the
result says which.

A frame in which a field would not be finite (a triangle collapsed to a line) is a failed
frame: its fields are written as missing (the datasets' ``_FillValue``), ``stress_valid`` is
false, and the run says so (:func:`invalid_frames`).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np

from structure.bending import MidedgeBending
from structure.grid import triangles_from_quads
from structure.hyperelastic import HyperelasticLaw, SaintVenantKirchhoff, TriangleMembrane
from structure.kernels import node_area_and_normal
from structure.model import MembraneModel
from structure.shell import ShellModel, ShellSettings
from structure.stress import INCOMPRESSIBLE_POISSON_RATIO, sheet_fields
from structure.tangent.membrane import MembraneTerm, regimes
from structure.topology import (creased, fold_clusters, free_triangles, inverted_area_fraction,
                                rest_angles, self_contact_nodes, triangle_adjacency,
                                wall_contact_area)
from structure.xpbd.kernels import WRINKLED
from structure.xpbd.model import XpbdModel

TRIANGLE_FIELDS = ("principal_resultant", "principal_direction", "principal_stress",
                   "bending_stress", "surface_stress", "von_mises_stress", "green_strain",
                   "log_strain", "thickness")
"""Per-triangle datasets of a membrane frame (:func:`structure.stress.sheet_fields`)."""
TOPOLOGY_SERIES = ("stress_valid", "fold_count", "inverted_area_fraction", "inversion_front_deg",
                   "wall_contact_area", "self_contact_nodes")
"""Per-frame datasets of a membrane frame: whether its fields are finite, and its topology
(module doc)."""


@dataclass(frozen=True)
class FieldRule:
    """What a run's stresses come from: ``law`` (text, for the result), ``term``
    (:class:`structure.tangent.membrane.MembraneTerm`), ``stress_law`` (the incompressible
    law that gives them, or None for the term's own), ``bending`` (or None),
    ``tension_field`` (wrinkles from its regimes, and no compression in the stresses), the
    model's D (N m), nu, rest thickness (m) and rest positions (n, 3) m."""

    law: str
    term: MembraneTerm
    stress_law: Optional[HyperelasticLaw]
    bending: Optional[MidedgeBending]
    tension_field: bool
    flexural_rigidity: float
    poisson_ratio: float
    thickness: float
    rest: np.ndarray

    def sheet(self, pos: np.ndarray) -> dict:
        """:func:`structure.stress.sheet_fields` at ``pos`` (n, 3) m under this rule."""
        return sheet_fields(self.term, pos, self.thickness, self.stress_law, self.tension_field,
                            self.bending, self.rest, self.flexural_rigidity, self.poisson_ratio)


FIELD_RULES: dict[str, Callable[[MembraneModel, object], FieldRule]] = {}
"""structure model name -> (MembraneModel, scene) -> :class:`FieldRule`."""


def field_rule(name: str):
    """Register the :class:`FieldRule` builder of structure model ``name``."""
    def register(build):
        FIELD_RULES[name] = build
        return build
    return register


def rubber_law(material) -> Optional[HyperelasticLaw]:
    """The incompressible neo-Hookean law of ``material``'s E (Pa) when its Poisson ratio is
    at or above :data:`structure.stress.INCOMPRESSIBLE_POISSON_RATIO`, else None."""
    if material.poisson_ratio >= INCOMPRESSIBLE_POISSON_RATIO:
        return HyperelasticLaw.from_youngs_modulus(material.youngs_modulus)
    return None


def _rubber_text(material, at: str, tension_field: bool = False) -> str:
    return (f"neo-hookean (incompressible, E = {material.youngs_modulus / 1e6:.4g} MPa"
            + (", no compression: tension field" if tension_field else "")
            + f") at the {at}'s strains")


@field_rule("minimisation")  # the XPBD model's energies, minimised
@field_rule("xpbd")
def _xpbd(model: MembraneModel, scene) -> FieldRule:
    xpbd = XpbdModel.from_membrane(model)
    mat = model.material
    rubber = rubber_law(mat)
    law = ("xpbd tension field" if xpbd.tension_field else "xpbd plane stress") \
        if rubber is None else _rubber_text(mat, "xpbd membrane", xpbd.tension_field)
    return FieldRule(law, MembraneTerm.from_xpbd(xpbd), rubber, xpbd.bending, xpbd.tension_field,
                     mat.flexural_rigidity, mat.poisson_ratio, mat.thickness,
                     model.node_rest_position)


@field_rule("shell")
def _shell(model: MembraneModel, scene) -> FieldRule:
    name = scene["structure"]["shell_law"]
    shell = ShellModel.from_membrane(model, ShellSettings(law=name))
    mat = model.material
    nu = getattr(shell.law, "poisson_ratio", mat.poisson_ratio)
    rubber = shell.law if isinstance(shell.law, HyperelasticLaw) else rubber_law(mat)
    law = name if rubber is shell.law or rubber is None else _rubber_text(mat, f"{name} shell")
    return FieldRule(law, MembraneTerm.from_triangle_membrane(shell.membrane, shell.law),
                     rubber, shell.bending, False, mat.flexural_rigidity, nu, mat.thickness,
                     model.node_rest_position)


@field_rule("thesis")
def _thesis(model: MembraneModel, scene) -> FieldRule:
    mat = model.material
    tri = triangles_from_quads(model.face_nodes)
    nu = min(mat.poisson_ratio, 0.4999)
    membrane = TriangleMembrane(model.node_rest_position, tri, mat.thickness)
    bending = MidedgeBending.build(model.node_rest_position, tri, mat.flexural_rigidity,
                                   mat.poisson_ratio)
    rubber = rubber_law(mat)
    law = "saint-venant-kirchhoff at the thesis membrane's strains" if rubber is None \
        else _rubber_text(mat, "thesis membrane")
    return FieldRule(law, MembraneTerm.from_triangle_membrane(
                         membrane, SaintVenantKirchhoff(mat.youngs_modulus, nu)),
                     rubber, bending, False, mat.flexural_rigidity, nu, mat.thickness,
                     model.node_rest_position)


@dataclass(frozen=True)
class SheetGeometry:
    """The rest data the topology needs: ``adjacency`` of the triangles, ``free_triangle``
    (m,) a triangle with a free node, ``node_area`` (n,) m^2 at rest, ``rest_polar`` and
    ``rest_azimuth`` (m,) deg of the triangles' rest centroids, ``triangle_area`` (m,) m^2,
    ``flat`` rest shape, ``rim_height`` (m), ``min_edge`` (m)."""

    adjacency: np.ndarray
    free_triangle: np.ndarray
    node_area: np.ndarray
    rest_polar: np.ndarray
    rest_azimuth: np.ndarray
    triangle_area: np.ndarray
    flat: bool
    rim_height: float
    min_edge: float

    @classmethod
    def of(cls, model: MembraneModel, triangles: np.ndarray) -> "SheetGeometry":
        rest = model.node_rest_position
        flat = bool(np.ptp(rest[:, 2]) == 0)
        polar, azimuth = rest_angles(rest[triangles].mean(axis=1), model.radius, flat)
        area, _ = node_area_and_normal(rest, model.grid_size, 1.0)
        e = rest[triangles[:, [1, 2, 0]]] - rest[triangles]
        tri_area = 0.5 * np.linalg.norm(np.cross(e[:, 0], -e[:, 2]), axis=1)
        return cls(triangle_adjacency(triangles), free_triangles(model.node_fixed, triangles), area,
                   polar, azimuth, tri_area, flat, float(rest[model.node_fixed, 2].mean()),
                   float(np.linalg.norm(e, axis=2).min()))


def folded_triangles(rule: FieldRule, geometry: SheetGeometry, pos: np.ndarray,
                     curvature: np.ndarray, radius: float) -> np.ndarray:
    """(m,) bool: the triangles a fold covers at ``pos`` (module doc)."""
    folded = creased(curvature, radius)
    if rule.tension_field:
        folded |= regimes(rule.term, pos) == WRINKLED
    return folded & geometry.free_triangle


def frame_fields(rule: FieldRule, geometry: SheetGeometry, model: MembraneModel,
                 pos: np.ndarray) -> tuple[dict, list[np.ndarray]]:
    """The datasets of one frame at ``pos`` (n, 3) m (module doc) and its folds (triangle
    index arrays)."""
    fields = rule.sheet(pos)
    folds = fold_clusters(folded_triangles(rule, geometry, pos, fields.pop("curvature"),
                                           model.radius), geometry.adjacency)
    free = ~model.node_fixed
    fraction, front = inverted_area_fraction(model.node_rest_position, pos, geometry.node_area,
                                             free, geometry.rim_height)
    out = {k: fields[k].astype(np.float32) for k in TRIANGLE_FIELDS}
    valid = all(np.all(np.isfinite(v)) for v in out.values())
    if not valid:  # written as missing, and the frame named as failed
        out = {k: np.full_like(v, np.nan) for k, v in out.items()}
    out.update(stress_valid=valid, fold_count=len(folds), inverted_area_fraction=fraction,
               inversion_front_deg=front,
               wall_contact_area=wall_contact_area(pos, geometry.node_area, free, model.radius,
                                                   geometry.min_edge),
               self_contact_nodes=len(self_contact_nodes(model.node_rest_position, pos,
                                                         geometry.min_edge)))
    return out, folds


def group_fields(rule: FieldRule, geometry: SheetGeometry, model: MembraneModel,
                 node_position: np.ndarray) -> tuple[dict, list[list[np.ndarray]]]:
    """:func:`frame_fields` over frames ``node_position`` (f, n, 3) m, stacked with a leading
    frame axis, and each frame's folds."""
    records, folds = [], []
    for pos in node_position:
        record, frame_folds = frame_fields(rule, geometry, model, pos)
        records.append(record)
        folds.append(frame_folds)
    return {k: np.asarray([r[k] for r in records]) for k in records[0]}, folds


def invalid_frames(groups: dict) -> list[str]:
    """'<group> frame k (tank fraction f)' of every frame of ``groups`` (name -> datasets)
    whose stress fields were not finite (``stress_valid`` false)."""
    out = []
    for name, g in groups.items():
        for k in np.nonzero(~np.asarray(g.get("stress_valid", []), dtype=bool))[0]:
            where = (f"t = {float(g['time'][k]):.4g} s" if "time" in g else
                     f"tank fraction {float(g['tank_fraction'][k]):.3f}"
                     if "tank_fraction" in g else "")
            out.append(f"{name} frame {k}" + (f" ({where})" if where else ""))
    return out
