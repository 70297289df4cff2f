"""First lateral slosh mode of the spherical tank by tank fraction: frequency, damping, slosh
mass, speed.

    python benchmarks/slosh_frequency.py [--fills 0.3 0.5 0.7] [--cells 16 24] [--limp]
                                         [--end-time 5.0]

Runs the bundled ``slosh-half`` scene (a 0.5 m/s^2 sin^2 lateral pulse over 0.1 s, then
inviscid free decay, 2 ms windows) at each tank fraction V / (4/3 pi R^3) and fluid grid, and
prints one JSON object with, per case, ``lambda1`` = omega^2 R / g, ``frequency_hz``, ``zeta``
(with standard errors), ``slosh_mass_fraction``, ``slosh_mass_height``, ``hinge_height``,
``wall_seconds`` and ``seconds_per_period``. ``--limp`` selects the limp diaphragm (the free
surface), the only surface model so far. Anchors at tank fraction 0.5: lambda1 = 1.5602 (rigid
half-full sphere, Budiansky 1960; NASTRAN demo d03031a), and the peer a user would pick for a
bare tank, OpenFOAM interFoam (v1912, this machine, 2 cores): 225 s for five periods at 34,776
cells with lambda1 off by -1.9 %. Writes ``benchmarks/output/slosh_frequency.png`` (lambda1
against tank fraction, one line per grid).
"""
from __future__ import annotations

import argparse
import json
import logging
from pathlib import Path

from fsi.build import build
from fsi.procedures import PROCEDURES
from fsi.scene import load_scene

OUTPUT = Path(__file__).resolve().parent / "output"
FIGURE = OUTPUT / "slosh_frequency.png"

#: Budiansky (1960): lambda1 = omega^2 R / g of the rigid half-full sphere
LAMBDA1_HALF = 1.5602
#: OpenFOAM interFoam v1912 on this machine: wall seconds for five periods, lambda1 error
INTERFOAM = {"seconds_five_periods": 225.0, "lambda1_error": -0.019, "cells": 34776}
KEYS = ("lambda1", "lambda1_std", "frequency_hz", "frequency_hz_std", "zeta", "zeta_std",
        "slosh_mass_fraction", "slosh_mass_height", "hinge_height", "pendulum_length",
        "tank_fraction", "wall_seconds", "seconds_per_period")


def run(fill: float, cells: int, end_time: float, surface: str) -> dict:
    """The bundled ``slosh-half`` at tank fraction ``fill`` on ``cells``^3: its numbers."""
    scene = load_scene("slosh-half")
    scene.values["slosh"].update(fill=fill, end_time=end_time, surface=surface)
    scene.values["fluid"]["cells"] = cells
    result = PROCEDURES["slosh"](build(scene), lambda fraction, message: None)
    out = dict(fill=fill, cells=cells, surface=surface)
    out.update({k: result.attrs.get(k) for k in KEYS})
    if result.attrs.get("analysis_failure"):
        out["analysis_failure"] = result.attrs["analysis_failure"]
    return out


def plot(cases: list[dict]) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    OUTPUT.mkdir(exist_ok=True)
    fig, ax = plt.subplots(figsize=(6, 4))
    for cells in sorted({c["cells"] for c in cases}):
        pts = sorted((c["fill"], c["lambda1"]) for c in cases
                     if c["cells"] == cells and c.get("lambda1") is not None)
        if pts:
            ax.plot(*zip(*pts), "o-", label=f"{cells}$^3$ cells")
    ax.plot([0.5], [LAMBDA1_HALF], "k*", ms=12, label="Budiansky 1960 (half full)")
    ax.set_xlabel("tank fraction V / (4/3 $\\pi$ R$^3$)")
    ax.set_ylabel("$\\lambda_1 = \\omega^2 R / g$")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.savefig(FIGURE, dpi=90, bbox_inches="tight")
    plt.close(fig)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fills", type=float, nargs="+", default=[0.5])
    parser.add_argument("--cells", type=int, nargs="+", default=[24])
    parser.add_argument("--limp", action="store_true",
                        help="the limp diaphragm (free surface); the default, the only model")
    parser.add_argument("--end-time", type=float, default=5.0, help="simulated seconds")
    args = parser.parse_args()
    logging.basicConfig(level=logging.WARNING)
    cases = [run(f, c, args.end_time, "limp") for f in args.fills for c in args.cells]
    plot(cases)
    half = [c for c in cases if c["fill"] == 0.5 and c.get("lambda1") is not None]
    for c in half:
        c["lambda1_error"] = c["lambda1"] / LAMBDA1_HALF - 1
        c["seconds_five_periods"] = 5 * c["seconds_per_period"]
        c["ratio_to_interfoam"] = c["seconds_five_periods"] / INTERFOAM["seconds_five_periods"]
    print(json.dumps(dict(cases=cases, anchor_lambda1_half=LAMBDA1_HALF, interfoam=INTERFOAM,
                          figure=str(FIGURE)), indent=1))


if __name__ == "__main__":
    main()
