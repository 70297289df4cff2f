"""What sets the elastic diaphragm's first slosh mode: one property varied at a time.

    python benchmarks/slosh_diaphragm.py [--cells 16] [--grid-size 14] [--end-time 3.0]
                                         [--cases base E/10 ...] [--no-limp]
                                         [--window-scheme first-order|scene] [--smoke]
    python benchmarks/slosh_diaphragm.py --replot A.json [B.json ...]

Runs the bundled ``slosh-diaphragm`` scene (the Table 4.1 diaphragm, a 0.5 m/s^2 sin^2 lateral
pulse over 0.1 s, then free decay) and its variants: Young's modulus / 10 (and / 100 by name)
(stiffness), density x 10 (mass), membrane grid N + 6 (how finely the folds are resolved),
tank fraction 0.3 and 0.7, the tension-field sheet (``membrane.wrinkling``) at 0.5, 0.3 and
0.7; by name, the flat diaphragm (``membrane.shape = "disc"``, taut at tank fraction 0.52:
a sheet that does not fold, for the membrane grid; and held by its rim ring only, without
the two-ring support's second ring), the XPBD sweeps per substep (1, 16, 32, 128: the
start's fold state and the membrane's stiffness), the window (1 and 4 ms) and the pulse's peak
(``pulse x0.125`` ... ``pulse x64`` times 0.5 m/s^2: linearity); and the limp surface (the
free-surface limit) at each tank fraction. Prints one JSON object with, per case,
``lambda1`` = omega^2 R / g, ``frequency_hz``, ``zeta`` (the first mode, the lowest damped at
zeta < 0.3; every fitted mode's in ``mode_*`` lists: a folded diaphragm splits the lateral
pair), ``slosh_mass_fraction``, ``slosh_mass_height``, the coupling's iterations and
unconverged windows and ``seconds_per_period``; the ratio of each lambda1 to
the limp surface's at the same tank fraction. Writes ``benchmarks/output/slosh_diaphragm.png``
(lambda1 and zeta by case) and ``slosh_diaphragm_by_fill.png`` (one panel per quantity against
the tank fraction: the limp surface, the full law's and the tension field's cases);
``--replot A.json B.json`` draws both from earlier runs' output without running.
Every case starts from the scene with the first-order window its tables in the README were
measured with (:data:`FIRST_ORDER`: 2 ms backward-Euler windows, Rhie-Chow faces, the node
fit), unless ``--window-scheme scene`` keeps the bundled scene's own (1 ms BDF2, every face's
memory, the surface mean); the ``second order, ...`` cases set their own window.
With two or more pulse cases the JSON has ``linearity``: per step up in the pulse, the first
mode's amplitude ratio over the pulse ratio and its frequency ratio (anchors 1; linear within
2 % and 0.5 %, the free-surface limit's criterion), and ``slosh_diaphragm_linearity.png``.
The JSON of a run that is not ``--smoke`` (``--replot`` too) also goes to
``docs/data/slosh_diaphragm.json``. ``--smoke``: :data:`SMOKE` (the base case and two pulses on
N = 6 for two windows, and the limp surface; the figures under ``benchmarks/output/smoke/``).
"""
from __future__ import annotations

import argparse
import json
import logging
import sys
from pathlib import Path

import numpy as np

from _report import SMOKE_HELP, emit, output_dir
from fsi.setup.build import build
from fsi.procedures import PROCEDURES
from fsi.scene import load_scene

OUTPUT = output_dir(False)
FIGURE = OUTPUT / "slosh_diaphragm.png"
BY_FILL = OUTPUT / "slosh_diaphragm_by_fill.png"
LINEARITY = OUTPUT / "slosh_diaphragm_linearity.png"
#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("cases", "figure", "by_fill")
#: --smoke: the options it sets (the membrane's static start is most of a case's time; at
#: N = 6 it takes a second)
SMOKE = dict(cases=["base", "pulse x1", "pulse x2"], grid_size=6, end_time=0.004)
#: the by-fill figure's families: label -> the cases of one membrane law at 0.3, 0.5, 0.7
FAMILIES = {"full law (N = {n})": ("base", "fill 0.3", "fill 0.7"),
            "tension field (N = {n})": ("tension field", "tension field, fill 0.3",
                                        "tension field, fill 0.7")}
#: the by-fill figure's panels: one quantity each, (key, axis label)
QUANTITIES = (("frequency_hz", "first mode (Hz)"), ("zeta", "damping ratio $\\zeta$"),
              ("slosh_mass_fraction", "first mode's x slosh mass / contents"),
              ("slosh_mass_height", "its height (m)"))
KEYS = ("lambda1", "frequency_hz", "zeta", "zeta_std", "slosh_mass_fraction",
        "slosh_mass_height", "tank_fraction", "mean_coupling_iterations",
        "windows_not_converged", "wall_seconds", "seconds_per_period", "first_mode_index",
        "centre_of_mass_amplitude")
MODE_KEYS = ("mode_frequency_hz", "mode_zeta", "mode_direction_deg", "mode_slosh_mass")

#: the relaxed (wrinkling) sheet, as the bundled slosh-tension-field scene runs it: the slack
#: sheet creeps, so its start stops at 1e-5 of a node length per substep
TENSION_FIELD = [("membrane", "wrinkling", lambda v: "tension-field"),
                 ("slosh", "start_tolerance", lambda v: 1e-5)]

#: the first-order window the README's one-at-a-time, linearity and grid tables were measured
#: with, before the bundled scene took the second-order one (``--window-scheme``)
FIRST_ORDER = [("coupling", "time_scheme", lambda v: "euler"),
               ("slosh", "window", lambda v: 2e-3),
               ("fluid", "face_memory", lambda v: "ring"),
               ("fluid", "pressure_map", lambda v: "node-fit")]
#: --window-scheme -> the changes every case starts from
WINDOW_SCHEMES = {"first-order": FIRST_ORDER, "scene": []}

#: case -> [(section, key, value from the base scene's value)]: each changes one thing
CASES = {
    "base": [],
    "E/10": [("membrane", "youngs_modulus", lambda v: 0.1 * v)],
    "E/100": [("membrane", "youngs_modulus", lambda v: 0.01 * v)],
    "density x10": [("membrane", "density", lambda v: 10.0 * v)],
    "N+6": [("membrane", "grid_size", lambda v: v + 6)],
    "fill 0.3": [("slosh", "fill", lambda v: 0.3)],
    "fill 0.7": [("slosh", "fill", lambda v: 0.7)],
    "tension field": TENSION_FIELD,
    "tension field, fill 0.3": TENSION_FIELD + [("slosh", "fill", lambda v: 0.3)],
    "tension field, fill 0.7": TENSION_FIELD + [("slosh", "fill", lambda v: 0.7)],
    "tension field, mixing 0.1": TENSION_FIELD + [("coupling", "mixing", lambda v: 0.1)],
    "sweeps 1": [("slosh", "constraint_sweeps", lambda v: 1)],
    "sweeps 16": [("slosh", "constraint_sweeps", lambda v: 16)],
    "sweeps 32": [("slosh", "constraint_sweeps", lambda v: 32)],
    "sweeps 128": [("slosh", "constraint_sweeps", lambda v: 128)],
    "start 1e-5": [("slosh", "start_tolerance", lambda v: 1e-5)],
    "simply supported": [("membrane", "support", lambda v: "simply-supported"),
                         ("slosh", "start_tolerance", lambda v: 1e-5)],
    "window 1 ms": [("slosh", "window", lambda v: 1e-3)],
    "window 4 ms": [("slosh", "window", lambda v: 4e-3)],
    "flat diaphragm": [("membrane", "shape", lambda v: "disc"),
                       ("slosh", "fill", lambda v: 0.52)],
}
#: the flat diaphragm held at its rim on r = R only (one fixed ring, the rim's slope held by
#: the bending; README, 'The flat diaphragm's second fixed ring')
CASES["flat diaphragm, rim ring only"] = CASES["flat diaphragm"] + [
    ("membrane", "support", lambda v: "simply-supported")]
#: the second-order window: BDF2, inviscid and linearised, every face keeping its history, the
#: pressure's surface mean at the nodes (README, 'Slosh with the diaphragm')
SECOND_ORDER = [("coupling", "time_scheme", lambda v: "bdf2"),
                ("fluid", "viscosity", lambda v: 0.0), ("fluid", "convection", lambda v: "none"),
                ("fluid", "face_memory", lambda v: "every-face"),
                ("fluid", "pressure_map", lambda v: "surface-mean")]
CASES.update({f"second order, window {w * 1e3:g} ms": SECOND_ORDER + [
    ("slosh", "window", lambda v, w=w: w)] for w in (1e-3, 5e-4, 2.5e-4)})
#: the pulse's peak times the scene's 0.5 m/s^2, doubling: where the response stops being linear
PULSE_SCALES = (0.125, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0)
CASES.update({f"pulse x{s:g}": [("motion", "amplitude", lambda v, s=s: [s * a for a in v])]
              for s in PULSE_SCALES})
CASES.update({f"{name}, window 1 ms": CASES[name] + CASES["window 1 ms"]
              for name in [f"pulse x{s:g}" for s in PULSE_SCALES]})
#: linear: doubling the pulse doubles the first mode's amplitude within 2 % and keeps its
#: frequency within 0.5 % (the free-surface limit's criterion, README 'Energy and linearity')
LINEAR_AMPLITUDE, LINEAR_FREQUENCY = 0.02, 0.005
DEFAULT_CASES = ["base", "E/10", "density x10", "N+6", "simply supported", "fill 0.3",
                 "fill 0.7", "tension field", "tension field, fill 0.3",
                 "tension field, fill 0.7"]
"""What a plain run varies; the sweeps, window and start-tolerance cases are asked for by name,
and E/100, whose coupling stalls (every window at the iteration limit from 1.60 s on,
N = 14)."""


def run(case: str, cells: int, grid_size: int, end_time: float, surface: str,
        window_scheme: str = "first-order") -> dict:
    scene = load_scene("slosh-diaphragm")
    v = scene.values
    v["slosh"].update(end_time=end_time, surface=surface)
    v["fluid"]["cells"] = cells
    v["membrane"]["grid_size"] = grid_size
    for section, key, change in WINDOW_SCHEMES[window_scheme] + CASES[case]:
        v[section][key] = change(v[section][key])
    result = PROCEDURES["slosh"](build(scene), lambda fraction, message: None)
    out = dict(case=case, surface=surface, cells=cells, grid_size=v["membrane"]["grid_size"],
               fill=v["slosh"]["fill"], youngs_modulus=v["membrane"]["youngs_modulus"],
               membrane_density=v["membrane"]["density"], window=v["slosh"]["window"],
               time_scheme=v["coupling"]["time_scheme"],
               constraint_sweeps=v["slosh"]["constraint_sweeps"],
               pulse_peak=float(max(abs(a) for a in v["motion"]["amplitude"])))
    if surface == "diaphragm":
        windows = result.groups["windows"]
        elastic = np.asarray(windows["membrane_elastic_energy"])
        after = np.asarray(windows["time"]) >= v["slosh"]["analysis_start"]
        # the folds' state: the elastic energy kept after the pulse against the start's
        out.update(start_elastic_energy=float(elastic[0]), elastic_energy_shift=(
            float(np.median(elastic[after]) - elastic[0]) if after.any() else None))
    out.update({k: result.attrs.get(k) for k in KEYS})
    for key in MODE_KEYS:  # every fitted lateral mode, ascending frequency
        if key in result.attrs:
            out[key] = [float(x) for x in result.attrs[key]]
    for key in ("analysis_failure", "failure"):
        if result.attrs.get(key):
            out[key] = result.attrs[key]
    return out


def _pulse_cases(cases: list[dict]) -> list[dict]:
    """The ``pulse x`` cases, by window, then by the pulse's peak."""
    return sorted((c for c in cases if c["case"].startswith("pulse x")),
                  key=lambda c: (c["window"], c["pulse_peak"]))


def linearity(cases: list[dict]) -> list[dict]:
    """Each step up in the pulse among the ``pulse x`` cases (by peak): the first mode's
    amplitude ratio over the pulse ratio (anchor 1) and frequency ratio (anchor 1), and
    whether both are within LINEAR_AMPLITUDE and LINEAR_FREQUENCY of their anchors; a step
    whose runs did not both end with a first mode is not linear and says why."""
    pulses = _pulse_cases(cases)
    steps = []
    for small, large in zip(pulses, pulses[1:]):
        if small["window"] != large["window"]:
            continue
        peaks = [small["pulse_peak"], large["pulse_peak"]]
        missing = next((c for c in (small, large) if not c.get("centre_of_mass_amplitude")),
                       None)
        if missing is not None:
            steps.append(dict(window=large["window"], pulse_peaks=peaks, linear=False, failure=(
                f"pulse peak {missing['pulse_peak']:g} m/s^2: "
                f"{missing.get('failure') or missing.get('analysis_failure') or 'no first mode'}")))
            continue
        scale = large["pulse_peak"] / small["pulse_peak"]
        amplitude = large["centre_of_mass_amplitude"] / small["centre_of_mass_amplitude"]
        frequency = large["frequency_hz"] / small["frequency_hz"]
        steps.append(dict(window=large["window"], pulse_peaks=peaks,
                          amplitude_ratio_over_pulse_ratio=amplitude / scale,
                          frequency_ratio=frequency,
                          linear=bool(abs(amplitude / scale - 1) <= LINEAR_AMPLITUDE
                                      and abs(frequency - 1) <= LINEAR_FREQUENCY)))
    return steps


def plot_linearity(cases: list[dict]) -> None:
    """Per window: the first mode's amplitude per unit pulse and its frequency, both over the
    window's smallest pulse's, and the elastic energy after the pulse, against the pulse's
    peak; a dotted line where that window's runs diverged."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    pulses = _pulse_cases(cases)
    fitted = [c for c in pulses if c.get("centre_of_mass_amplitude")]
    if len(fitted) < 2:
        return
    panels = (("mode 1 amplitude per unit peak,\nover the smallest pulse's", LINEAR_AMPLITUDE),
              ("mode 1 frequency,\nover the smallest pulse's", LINEAR_FREQUENCY),
              ("|elastic energy after the pulse,\nover the start's| (median, J)", None))
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.4))
    for window in sorted({c["window"] for c in pulses}, reverse=True):
        series = [c for c in fitted if c["window"] == window]
        if not series:
            continue
        first = series[0]
        peak = [c["pulse_peak"] for c in series]
        values = ([(c["centre_of_mass_amplitude"] / c["pulse_peak"])
                   / (first["centre_of_mass_amplitude"] / first["pulse_peak"]) for c in series],
                  [c["frequency_hz"] / first["frequency_hz"] for c in series],
                  [abs(c["elastic_energy_shift"]) for c in series])
        label = f"{window * 1e3:g} ms windows"
        lines = [ax.plot(peak, v, "o-", label=label)[0] for ax, v in zip(axes, values)]
        failed = [c["pulse_peak"] for c in pulses if c["window"] == window
                  and not c.get("centre_of_mass_amplitude")]
        if failed:
            for ax, line in zip(axes, lines):
                ax.axvline(min(failed), color=line.get_color(), ls=":",
                           label=f"{label}: diverged from here")
    for ax, (label, band) in zip(axes, panels):
        if band is not None:  # the linear criterion, about the smallest pulse's value
            ax.axhspan(1 - band, 1 + band, color="tab:green", alpha=0.15, label="linear")
            low, high = ax.get_ylim()
            ax.set_ylim(min(low, 1 - 2 * band), max(high, 1 + 2 * band))
        ax.set_xscale("log")
        ax.set_xlabel("pulse peak (m/s$^2$)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3, which="both")
    axes[2].set_yscale("log")
    axes[0].legend(fontsize=7)
    fig.suptitle("diaphragm at tank fraction 0.5: linearity in the pulse")
    fig.tight_layout()
    fig.savefig(LINEARITY, dpi=90)
    plt.close(fig)


def plot(cases: list[dict]) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    OUTPUT.mkdir(parents=True, exist_ok=True)
    shown = [c for c in cases if c.get("lambda1") is not None]
    labels = [f"{c['case']}\n{c['surface']}" for c in shown]
    fig, axes = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    axes[0].bar(labels, [c["lambda1"] for c in shown])
    axes[0].set_yscale("log")
    axes[0].set_ylabel("$\\lambda_1 = \\omega^2 R / g$")
    axes[1].bar(labels, [c["zeta"] for c in shown])
    axes[1].set_ylabel("$\\zeta$")
    axes[1].tick_params(axis="x", labelsize=7)
    for ax in axes:
        ax.grid(alpha=0.3, axis="y")
    fig.savefig(FIGURE, dpi=90, bbox_inches="tight")
    plt.close(fig)
    plot_by_fill(cases)
    plot_linearity(cases)


def plot_by_fill(cases: list[dict]) -> None:
    """One panel per quantity against the tank fraction: the limp surface (the free-surface
    limit) and each membrane law's family, where the cases ran."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker
    lines = {"limp (free surface)": [c for c in cases if c["surface"] == "limp"]}
    for label, names in FAMILIES.items():
        members = [c for c in cases if c["surface"] == "diaphragm" and c["case"] in names]
        if members:
            lines[label.format(n=members[0]["grid_size"])] = members
    fig, axes = plt.subplots(1, len(QUANTITIES), figsize=(4 * len(QUANTITIES), 3.4))
    for ax, (key, label) in zip(axes, QUANTITIES):
        for name, members in lines.items():
            points = sorted((c["tank_fraction"] or c["fill"], c[key]) for c in members
                            if c.get(key) is not None)
            if points:
                ax.plot(*zip(*points), "o-", label=name)
        ax.set_xlabel("tank fraction V / (4/3 $\\pi R^3$)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].set_yscale("log")
    axes[0].yaxis.set_major_formatter(matplotlib.ticker.ScalarFormatter())
    axes[0].yaxis.set_minor_formatter(matplotlib.ticker.ScalarFormatter())
    if axes[0].get_legend_handles_labels()[0]:
        axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(BY_FILL, dpi=90)
    plt.close(fig)


def _output(cases: list[dict]) -> dict:
    out = dict(cases=cases, figure=str(FIGURE), by_fill=str(BY_FILL))
    steps = linearity(cases)
    if steps:
        out.update(linearity=steps, linearity_anchors=dict(
            amplitude_ratio_over_pulse_ratio=1.0, frequency_ratio=1.0),
            linearity_goals=dict(amplitude=LINEAR_AMPLITUDE, frequency=LINEAR_FREQUENCY),
            linearity_figure=str(LINEARITY))
    return out


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, default=16)
    parser.add_argument("--grid-size", type=int, default=14)
    parser.add_argument("--end-time", type=float, default=3.0, help="simulated seconds")
    parser.add_argument("--cases", nargs="+", default=DEFAULT_CASES, choices=list(CASES))
    parser.add_argument("--no-limp", action="store_true", help="skip the limp references")
    parser.add_argument("--window-scheme", choices=sorted(WINDOW_SCHEMES),
                        default="first-order", help="what every case starts from: the "
                        "first-order window of the README's tables, or the scene's own")
    parser.add_argument("--replot", nargs="+", type=Path, metavar="JSON",
                        help="draw the figures from earlier runs' printed JSON, run nothing")
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    if args.smoke:
        vars(args).update(SMOKE)
        _use_output(output_dir(True))
    if args.replot:
        cases = [c for path in args.replot for c in json.loads(path.read_text())["cases"]]
        plot(cases)
        emit("slosh_diaphragm", _output(cases), args.smoke)
        return
    logging.basicConfig(level=logging.WARNING)
    cases = []
    for c in args.cases:  # each case on stderr as it ends, so a stopped sweep keeps them
        cases.append(run(c, args.cells, args.grid_size, args.end_time, "diaphragm",
                         args.window_scheme))
        print(json.dumps(cases[-1]), file=sys.stderr, flush=True)
    if not args.no_limp:
        fills = sorted({c["fill"] for c in cases})
        limp = {f: run({0.3: "fill 0.3", 0.7: "fill 0.7"}.get(f, "base"), args.cells,
                       args.grid_size, args.end_time, "limp", args.window_scheme)
                for f in fills}
        for c in cases:
            ref = limp[c["fill"]].get("lambda1")
            if c.get("lambda1") and ref:
                c["lambda1_over_limp"] = c["lambda1"] / ref
        cases += list(limp.values())
    plot(cases)
    emit("slosh_diaphragm", _output(cases), args.smoke)


def _use_output(folder: Path) -> None:
    """Write the figures under ``folder``."""
    global OUTPUT, FIGURE, BY_FILL, LINEARITY
    OUTPUT = folder
    FIGURE, BY_FILL, LINEARITY = (folder / path.name for path in (FIGURE, BY_FILL, LINEARITY))


if __name__ == "__main__":
    main()
