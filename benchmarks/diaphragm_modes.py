"""The diaphragm's slosh modes from one eigenvalue problem, against the coupled time domain.

    python benchmarks/diaphragm_modes.py [--grid-sizes 14 20 26] [--cells 16 24]
                                         [--minimised-grids 14 26 38] [--smoke]

The ``modes`` rung with ``modes.surface = "diaphragm"``
(:func:`fsi.slosh.hydroelastic.diaphragm_modes`: the membrane's tangent stiffness about its
loaded equilibrium, its mass and the liquid's added mass on the fluid grid) for two
diaphragms, each beside the time domain's first modes on the same grids (the ``slosh``
procedure's free decay, measured in the notes named in :data:`TIME_DOMAIN`):

* ``flat``: the flat diaphragm held by its rim ring (``membrane.shape = "disc"``,
  ``support = "simply-supported"``) at tank fraction 0.52, on each membrane grid of
  ``--grid-sizes`` with 16^3 cells and on N = 14 with each of ``--cells``;
* ``hemisphere``: the Table 4.1 diaphragm at half fill, N = 14, 16^3 cells (its folds split
  the lateral pair), from the XPBD relaxation's start as the time domain's run; then on each
  grid of ``--minimised-grids`` from the minimisation's start (``start_solver =
  "minimisation"``, :mod:`fsi.setup.static_start`), which reaches grids the relaxation's
  start does not in minutes.

Prints one JSON object: ``cases``, each {``diaphragm``, ``start_solver``, ``grid_size``,
``cells``, ``fill``,
``frequency_hz`` (the first modes), ``slosh_mass_fraction``, ``direction_deg``,
``unstable``, ``dofs``, ``wall_seconds``, ``time_domain`` (its frequencies and slosh mass
fraction where measured) and ``ratio`` (the first mode's frequency over the time domain's)}.
A full run's JSON also goes to ``docs/data/diaphragm_modes.json``. ``--smoke``: the flat
diaphragm at N = 10 on 12^3 cells.
"""
from __future__ import annotations

import argparse
import logging

import numpy as np

from _report import SMOKE_HELP, emit
from fsi.scene import load_scene
from fsi.setup.build import build
from fsi.procedures.modes import diaphragm_modes

DOC_FIELDS = ("cases",)
COUNT = 6
"""Modes computed per case."""
DIAPHRAGMS = {
    "flat": ({"shape": "disc", "support": "simply-supported"}, 0.52),
    "hemisphere": ({}, 0.5),
}
"""name -> (its [membrane] keys beside grid_size, the tank fraction)."""
TIME_DOMAIN = {
    ("flat", 14, 16): {"frequency_hz": [3.1590], "slosh_mass_fraction": 0.473,
                       "source": "docs/notes/lateral-compliance.md, rim ring only"},
    ("flat", 20, 16): {"frequency_hz": [3.1413], "slosh_mass_fraction": 0.470,
                       "source": "docs/notes/lateral-compliance.md, rim ring only"},
    ("flat", 26, 16): {"frequency_hz": [3.1312], "slosh_mass_fraction": 0.468,
                       "source": "docs/notes/lateral-compliance.md, rim ring only"},
    ("flat", 14, 24): {"frequency_hz": [3.0643], "slosh_mass_fraction": 0.445,
                       "source": "docs/notes/lateral-compliance.md, fluid grid"},
    ("flat", 14, 32): {"frequency_hz": [3.0405], "slosh_mass_fraction": 0.434,
                       "source": "docs/notes/lateral-compliance.md, fluid grid"},
    ("hemisphere", 14, 16): {"frequency_hz": [7.00, 8.92], "slosh_mass_fraction": None,
                             "source": "fsi/slosh/modes.py (two-channel fit of a free decay)"},
}
"""The time domain's first modes (Hz) and first slosh mass fraction, measured."""


def run(diaphragm: str, grid_size: int, cells: int, start_solver: str = "relaxation") -> dict:
    keys, fill = DIAPHRAGMS[diaphragm]
    setup = build(load_scene("slosh-diaphragm").with_keys(
        {"membrane": {"grid_size": grid_size, **keys}}))
    found = diaphragm_modes(setup, fill, cells, COUNT, start_solver)
    frequency = np.sqrt(found.omega2) / (2 * np.pi)
    case = dict(diaphragm=diaphragm, start_solver=start_solver, grid_size=grid_size,
                cells=cells, fill=fill, level=found.level,
                frequency_hz=frequency.tolist(),
                slosh_mass_fraction=(found.slosh_mass / found.mass).tolist(),
                direction_deg=found.direction_deg.tolist(), unstable=found.unstable,
                converged=found.converged, dofs=found.dofs, wall_seconds=found.seconds)
    reference = TIME_DOMAIN.get((diaphragm, grid_size, cells))
    if reference is not None and start_solver == "relaxation":
        case["time_domain"] = reference
        case["ratio"] = float(frequency[0] / reference["frequency_hz"][0])
    return case


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--grid-sizes", type=int, nargs="+", default=[14, 20, 26])
    parser.add_argument("--cells", type=int, nargs="+", default=[16, 24])
    parser.add_argument("--minimised-grids", type=int, nargs="*", default=[14, 26, 38])
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args()
    logging.basicConfig(level=logging.WARNING)
    if args.smoke:
        cases = [run("flat", 10, 12)]
    else:
        cases = [run("flat", n, 16) for n in args.grid_sizes]
        cases += [run("flat", 14, c) for c in args.cells if c != 16]
        cases.append(run("hemisphere", 14, 16))
        cases += [run("hemisphere", n, 16, "minimisation") for n in args.minimised_grids]
    emit("diaphragm_modes", dict(cases=cases), args.smoke)


if __name__ == "__main__":
    main()
