"""Elastic tube 1D: the accelerations of the coupling library on the stiff partitioned FSI case
of :mod:`cases.elastic_tube` (equations, references and what limits the iterations in its
docstring).

    python benchmarks/elastic_tube.py [--smoke]

Writes ``benchmarks/output/elastic_tube_iterations.png`` (coupling iterations per window, one
panel per fluid discretisation) and prints one JSON object: at its top level the mean coupling
iterations per window of every acceleration in ``coupling.ACCELERATIONS`` on the published
case (null when a window does not converge within ``MAX_ITERATIONS``) and the settings used;
under ``discretisations`` the same for each fluid discretisation of :data:`DISCRETISATIONS`,
with the comparison with preCICE, the IQN-ILS solution's largest relative difference from a
monolithic reference and the interface-Newton bounds. A full run's JSON also goes to
``docs/data/elastic_tube.json``. ``--smoke``: the first :data:`SMOKE_WINDOWS` windows of each
discretisation (the figure under ``benchmarks/output/smoke/``).
"""
from __future__ import annotations

import argparse
from dataclasses import asdict
from pathlib import Path

import numpy as np

from _report import SMOKE_HELP, emit, output_dir
from cases.elastic_tube import (ACCELERATION_SETTINGS, COUPLING_TOLERANCE, DISCRETISATIONS, DT,
                                EXTRAPOLATION_ORDER, MAX_ITERATIONS, N_WINDOWS, PUBLISHED,
                                REFERENCE_TOLERANCE, Discretisation, couple, coupling_settings,
                                interface_newton, monolithic_reference,
                                precice_tutorial_settings, relative_difference)
from coupling import ACCELERATIONS

GOALS = {"iqn_ils_mean_iterations": 4.0, "relative_difference": 1e-4}

FIGURE_NAME = "elastic_tube_iterations.png"
#: the JSON's top-level keys the documentation reads (aitken and constant are null where they
#: fail)
DOC_FIELDS = ("iqn-ils", "iqn-imvj", "failures", "goals", "discretisations")
#: --smoke: windows per run (of N_WINDOWS)
SMOKE_WINDOWS = 5


def _plot(panels: dict, path: Path) -> None:
    """Iterations per window, one panel per discretisation: ``panels`` maps a discretisation
    name to {label: Outcome}."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(panels), figsize=(7 * len(panels), 4.5), sharey=True)
    for ax, (name, outcomes) in zip(np.atleast_1d(axes), panels.items()):
        disc = DISCRETISATIONS[name]
        for label, out in outcomes.items():
            windows = np.arange(len(out.iterations))
            line, = ax.plot(windows, out.iterations, marker=".", lw=1,
                            label=label + (f" (fails at window {windows[-1]})" if out.failure
                                           else f" (mean {out.mean_iterations:.2f})"))
            if out.failure:
                ax.plot(windows[-1], out.iterations[-1], "x", ms=10, color=line.get_color())
        ax.axhline(GOALS["iqn_ils_mean_iterations"], color="k", ls="--", lw=0.8,
                   label="goal of the IQN-ILS mean")
        ax.set_yscale("log")
        ax.set_xlabel(f"time-window index (dt = {DT:g} s)")
        ax.set_title(f"fluid '{name}': dx = {disc.cell_length:g} m, alpha = {disc.alpha:g} "
                     f"(preCICE: {disc.precice_mean_iterations:g})", fontsize=10)
        ax.legend(fontsize=7)
        ax.grid(True, which="both", alpha=0.3)
    np.atleast_1d(axes)[0].set_ylabel("coupling iterations")
    fig.suptitle(f"Elastic tube 1D, serial-implicit, relative tolerance {COUPLING_TOLERANCE:g}")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def study(disc: Discretisation, n_windows: int = N_WINDOWS):
    """Every acceleration (this benchmark's setup), the tutorial's setup, the monolithic
    reference and the interface-Newton bounds on one discretisation, ``n_windows`` windows
    each: (outcomes for the plot, JSON summary)."""
    outcomes = {name: couple(coupling_settings(name), n_windows=n_windows, disc=disc)
                for name in sorted(ACCELERATIONS)}
    tutorial = couple(precice_tutorial_settings(), solid_first=False, n_windows=n_windows,
                      disc=disc)
    p_ref, a_ref = monolithic_reference(n_windows=n_windows, disc=disc)
    iqn = outcomes["iqn-ils"]
    difference = {"pressure": relative_difference(iqn.pressure, p_ref[:len(iqn.pressure)]),
                  "area": relative_difference(iqn.area, a_ref[:len(iqn.area)])}
    summary = {
        "fluid": {"cell_length": disc.cell_length, "alpha": disc.alpha, "source": disc.source},
        "mean_iterations": {name: o.mean_iterations for name, o in outcomes.items()},
        "failures": {name: o.failure for name, o in outcomes.items() if o.failure},
        "precice_tutorial_setup": {
            "this_code": tutorial.mean_iterations,
            "precice": disc.precice_mean_iterations,
            "ratio": (None if tutorial.mean_iterations is None else round(
                tutorial.mean_iterations / disc.precice_mean_iterations, 3))},
        "iqn_ils_vs_monolithic_reference": {
            "max_relative_difference": difference,
            "measure": "max over windows of max|u - u_ref| / max|u_ref|",
            "reference": f"monolithic Newton, |F|/|(v, p)| <= {REFERENCE_TOLERANCE:g}"},
        "interface_newton_bounds": {
            "newton_on_pressure_solid_first": float(np.mean(
                interface_newton("pressure", n_windows=n_windows, disc=disc))),
            "newton_on_area_fluid_first": float(np.mean(
                interface_newton("area", n_windows=n_windows, disc=disc))),
            "chord_with_previous_window_jacobian_on_pressure": float(np.mean(
                interface_newton("pressure", chord=True, n_windows=n_windows, disc=disc))),
            "note": "exact interface Jacobian, same measures and extrapolation"},
        "goals_met": {
            "iqn_ils_mean_iterations": bool(iqn.mean_iterations is not None and
                                            iqn.mean_iterations <= GOALS[
                                                "iqn_ils_mean_iterations"]),
            "relative_difference": bool(max(difference.values())
                                        <= GOALS["relative_difference"])},
    }
    panel = {**outcomes, "iqn-ils, preCICE tutorial setup (fluid first)": tutorial}
    return panel, summary


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    n_windows = SMOKE_WINDOWS if args.smoke else N_WINDOWS
    figure = output_dir(args.smoke) / FIGURE_NAME
    panels, summaries = {}, {}
    for name, disc in DISCRETISATIONS.items():
        panels[name], summaries[name] = study(disc, n_windows)
    _plot(panels, figure)
    published = summaries[PUBLISHED.name]
    out = dict(published["mean_iterations"])
    out.update({
        "failures": published["failures"],
        "coupling": {"scheme": "implicit-serial", "first": "solid", "second": "fluid",
                     "accelerated": ["pressure"], "extrapolation_order": EXTRAPOLATION_ORDER,
                     "relative_tolerance": COUPLING_TOLERANCE,
                     "max_iterations": MAX_ITERATIONS, "on_max_iterations": "error"},
        "iqn_ils_settings": asdict(ACCELERATION_SETTINGS),
        "goals": GOALS,
        "discretisations": summaries,
        "figure": str(figure),
    })
    emit("elastic_tube", out, args.smoke)
    return out


if __name__ == "__main__":
    main()
