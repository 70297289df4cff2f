"""The scene's diaphragm as a shell of revolution (:mod:`structure.axisymmetric`): the
``[axisymmetric]`` table (meridian grid, wall, fills, stability table) and the (shell, load)
it builds, for the ``shell-of-revolution`` procedure and for the ``axisymmetric`` static start
of a coupled run (:mod:`fsi.setup.static_start`)."""
from __future__ import annotations

from typing import Optional

import numpy as np

from structure.axisymmetric import AxisymmetricLoad, barrier_wall, law_of, shell_of_revolution
from structure.model import Material
from structure.stress import INCOMPRESSIBLE_POISSON_RATIO

from fsi.registry import Key, SceneError, Table


def _fills(v) -> bool:
    return (isinstance(v, list) and len(v) >= 2
            and all(isinstance(c, (int, float)) and not isinstance(c, bool) for c in v)
            and v[0] == 0 and all(0 <= a < b < 1 for a, b in zip(v, v[1:])))


def _slosh_fills(v) -> bool:
    return (isinstance(v, list)
            and all(isinstance(c, (int, float)) and not isinstance(c, bool) for c in v)
            and all(0 < c < 1 for c in v) and all(a < b for a, b in zip(v, v[1:])))


def _check_slosh_fills(table: dict) -> None:
    fills = np.asarray(table["fills"], dtype=float)
    for f in table["slosh_fills"]:
        if not np.any(np.abs(fills - f) <= 1e-9):
            raise SceneError(f"scene key 'axisymmetric.slosh_fills' holds {f!r}, which is not "
                             f"one of axisymmetric.fills: allowed, tank fractions of the fill")


AXISYMMETRIC = Table({
    "elements": Key(int, 256, lambda v: 8 <= v <= 4096, "integer 8..4096",
                    "cubic Hermite elements on the meridian (256 converges the Table 4.1 "
                    "diaphragm's level to 2e-5 of rho g a; "
                    "docs/validation/shell-of-revolution.md)"),
    "rim_ratio": Key(float, 0.3, lambda v: 0 < v <= 3, "0 < value <= 3",
                     "the rim element's length over the mean (grading toward the clamp)"),
    "wall_band": Key(float, 1e-4, lambda v: 0 < v <= 1e-2, "0 < value <= 0.01",
                     "the tank wall's barrier band beyond the tank radius, as a fraction of it"),
    "fills": Key(list, [round(0.025 * k, 4) for k in range(40)] + [0.99], _fills,
                 "increasing tank fractions from 0, each below 1",
                 "tank fractions V / (4/3 pi R^3) of the fill and, reversed, of the drain"),
    "wave_numbers": Key(int, 30, lambda v: 1 <= v <= 200, "integer 1..200",
                        "the stability table's circumferential wave numbers n = 1 ... this"),
    "samples": Key(int, 121, lambda v: 3 <= v <= 10001, "integer 3..10001",
                   "points along the meridian at which each state's fields are written"),
    "slosh_fills": Key(list, [round(0.1 * k, 4) for k in range(1, 10)], _slosh_fills,
                       "increasing tank fractions in (0, 1), each one of fills; [] for none",
                       "tank fractions at which the fill's n = 1 slosh mode is found on the "
                       "liquid's potential flow (fsi.slosh.axisymmetric)"),
}, lambda table: _check_slosh_fills(table))
"""[axisymmetric]: the meridian grid, the wall, the fills and the stability table."""


def build(scene, elements: Optional[int] = None, wrinkling: Optional[str] = None):
    """(shell, load) of the scene (module doc) on ``elements`` meridian elements (the
    scene's ``axisymmetric.elements`` by default), its membrane's ``wrinkling`` unless
    given."""
    table, m = scene["axisymmetric"], scene["membrane"]
    material = Material(m["thickness"], m["density"], m["youngs_modulus"], m["poisson_ratio"],
                        m["wrinkling"] if wrinkling is None else wrinkling)
    law = "neo-hookean" if material.poisson_ratio >= INCOMPRESSIBLE_POISSON_RATIO \
        else scene["structure"]["shell_law"]
    liquid = scene["liquid"]
    gravity = float(np.linalg.norm(liquid["body_acceleration"]))
    radius = scene["tank"]["radius"]
    scale = liquid["density"] * gravity * radius
    shell = shell_of_revolution("hemisphere", radius, material, law_of(material, law),
                                elements or table["elements"], support=m["support"],
                                rim_ratio=table["rim_ratio"],
                                wall=barrier_wall(radius, scale, table["wall_band"]))
    load = AxisymmetricLoad(liquid_density=liquid["density"], gravity=gravity,
                            volume_target=0.0)
    return shell, load
