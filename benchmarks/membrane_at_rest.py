"""Does the membrane at its static equilibrium stay at rest when its inertia is switched on?

    python benchmarks/membrane_at_rest.py [--cases NAME ...] [--windows 40] [--smoke]

Each case is the bundled ``diaphragm-fill``'s membrane (Table 4.1, clamped, tank fraction
0.5) at one membrane grid N and in-plane law: its static start (damped XPBD under the
hydrostatic liquid, the coupled fill's own start), then ``--windows`` windows of 2 ms done
with the membrane's inertia (the coupled fill's inertial window, ``substeps``) and no liquid:
each window's node pressure is the hydrostatic part rho b . x at the nodes' positions at its
start (the liquid's reduced pressure taken as zero), the liquid volume held at the start's.
A membrane in equilibrium should stay at rest, its kinetic energy at the start's residual
motion.  Reported per case: the start's pressure level and substeps, the membrane's kinetic
energy (J) and largest node speed (m/s) after each window, and the ratio of the last
window's kinetic energy to the first's.

Writes ``benchmarks/output/membrane_at_rest.json`` and ``membrane_at_rest.png`` (kinetic
energy against time, one line per case).  Prints one JSON object (a full run also writes it
to ``docs/data/membrane_at_rest.json``); about 6 min.  ``--smoke``: N = 14 under the full law,
two windows (its files under ``benchmarks/output/smoke/``).
"""
from __future__ import annotations

import argparse
import json
import logging
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from _report import SMOKE_HELP, emit, output_dir  # noqa: E402
from fsi.coupled.adapters import PRESSURE, MembraneParticipant  # noqa: E402
from fsi.setup.build import build  # noqa: E402
from fsi.procedures.coupled_fill import membrane_settings, static_start  # noqa: E402
from fsi.scene import load_scene  # noqa: E402
from structure.volume import liquid_volume  # noqa: E402
from structure.xpbd import XpbdModel  # noqa: E402

#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("window", "windows", "runs")
#: --smoke: the cheapest case (the tension field's start alone takes about 25 s), two windows
SMOKE_CASES, SMOKE_WINDOWS = ["N = 14, full law"], 2
WINDOW = 0.002
"""s: the bundled diaphragm-fill's window."""
CASES = {
    "N = 14, full law": dict(grid_size=14, wrinkling="none"),
    "N = 26, full law": dict(grid_size=26, wrinkling="none"),
    "N = 14, tension field": dict(grid_size=14, wrinkling="tension-field"),
    "N = 20, tension field": dict(grid_size=20, wrinkling="tension-field"),
    "N = 26, tension field": dict(grid_size=26, wrinkling="tension-field"),
    "N = 26, tension field, substep fraction 0.1": dict(grid_size=26, wrinkling="tension-field",
                                                        substep_fraction=0.1),
}
"""name -> membrane.grid_size, membrane.wrinkling and dynamics.substep_fraction (default:
the scene's)."""


def run_case(grid_size: int, wrinkling: str, windows: int,
             substep_fraction: float | None = None) -> dict:
    keys = {"membrane": dict(grid_size=grid_size, wrinkling=wrinkling)}
    if substep_fraction is not None:
        keys["dynamics"] = dict(substep_fraction=substep_fraction)
    setup = build(load_scene("diaphragm-fill").with_keys(keys))
    model = XpbdModel.from_membrane(setup.model)
    settings = membrane_settings(setup)
    t0 = time.perf_counter()
    start, info = static_start(setup, model, settings)
    start_seconds = time.perf_counter() - t0
    volume = liquid_volume(setup.model, start.node_position)
    body = np.asarray(setup.liquid.body_acceleration, dtype=float)
    rho = setup.liquid.density
    membrane = MembraneParticipant(model, start, settings, lambda t: volume, body,
                                   info.pressure_level, "substeps")
    mass = setup.model.node_mass
    times, energy, speed = [], [], []
    for k in range(windows):
        pressure = rho * membrane.state.node_position @ body
        membrane.solve_window(k * WINDOW, WINDOW, {PRESSURE: pressure})
        v = membrane.state.node_velocity
        times.append((k + 1) * WINDOW)
        energy.append(0.5 * float((mass * (v**2).sum(axis=1)).sum()))
        speed.append(float(np.linalg.norm(v, axis=1).max()))
    return dict(grid_size=grid_size, wrinkling=wrinkling, substep=settings.dt,
                start_pressure_level=float(info.pressure_level), start_steps=int(info.steps),
                start_converged=bool(info.converged), start_seconds=start_seconds,
                time=times, kinetic_energy=energy, node_speed_max=speed,
                energy_growth=energy[-1] / energy[0] if energy[0] > 0 else float("inf"))


def plot(runs: dict):
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    for name, r in runs.items():
        ax.semilogy(np.asarray(r["time"]) * 1e3, r["kinetic_energy"], label=name)
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("membrane kinetic energy (J)")
    ax.set_title("the diaphragm at its static start, with inertia and no liquid", fontsize=9)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    return fig


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    parser.add_argument("--windows", type=int, default=40, help="2 ms windows per case")
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    if args.smoke:
        args.cases, args.windows = SMOKE_CASES, SMOKE_WINDOWS
    output = output_dir(args.smoke)
    logging.basicConfig(level=logging.ERROR)
    runs = {name: run_case(windows=args.windows, **CASES[name]) for name in args.cases}
    output.mkdir(parents=True, exist_ok=True)
    plot(runs).savefig(output / "membrane_at_rest.png", dpi=120)
    summary = dict(window=WINDOW, windows=args.windows, runs=runs,
                   png=str(output / "membrane_at_rest.png"))
    (output / "membrane_at_rest.json").write_text(json.dumps(summary, indent=1))
    emit("membrane_at_rest", summary, args.smoke)
    return 0


if __name__ == "__main__":
    sys.exit(main())
