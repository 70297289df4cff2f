"""Where the partitioned schemes fail on the diaphragm itself: constant under-relaxation
against the added-mass bound, the explicit scheme, Aitken and IQN-ILS.

    python benchmarks/diaphragm_stability.py [--omegas 0.005 0.01 ...] [--windows 3]
                                             [--mixings 0.3 0.1 0.03] [--smoke]

The case: the bundled ``diaphragm-fill`` (Table 4.1 diaphragm, N = 14, 16^3 cells, windows of
2 ms, the port flow ramping up) for its first ``--windows`` windows, run with each scheme.

Prediction (Causin, Gerbeau & Nobile 2005; ``cases/added_mass.py``): Dirichlet-Neumann
iterations relaxed by a constant omega converge iff omega < 2 m / (m + rho_f mu_max), m the
membrane's mass per area (rho_m t = 1.90 kg/m^2) and mu_max the largest added-mass length of
the interface.  Estimated here by the n = 1 surface mode of a liquid sphere,
mu_1 = R / n = R (Lamb, Hydrodynamics, Sec. 91: interior potential r^n Y_n), so
omega_max ~ 2 m / (m + rho_f R) = 0.018 and the mass ratio m / (rho_f R) = 0.009.  The
membrane's stiffness adds k dt^2 to m for each mode; its lateral n = 1 mode has almost none.

Measured: for each omega, whether every window converges within ``--max-iterations`` (and the
mean iterations), or the last pressure residual stays below 1 (not converged: slow), or not
(diverged); the largest converging and smallest diverging omega; the explicit scheme over
``--explicit-windows`` windows (its largest node speed against the implicit run's); Aitken and
IQN-ILS iterations per window, and IQN-ILS with each ``--mixings`` beta (``coupling.mixing``:
the step outside the secants' span relaxed by beta instead of taken whole).
Writes ``benchmarks/output/diaphragm_stability.json`` and ``.png``; prints one JSON object
(also written to ``docs/data/diaphragm_stability.json``). Default run: about 2 min on 2 cores.
``--smoke``: one window, omegas 0.07 and 0.2 (at most 150 iterations), one mixing, two
explicit windows (its files under ``benchmarks/output/smoke/``).
"""
from __future__ import annotations

import argparse
import json
import re
import logging
import sys
import time
from pathlib import Path

import numpy as np

from _report import SMOKE_HELP, emit, output_dir
from fsi.setup.build import build
from fsi.constants import MEMBRANE_DENSITY, MEMBRANE_THICKNESS, TANK_RADIUS, WATER_DENSITY
from fsi.procedures import PROCEDURES
from fsi.scene import load_scene

#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("predicted", "constant", "largest_converging_omega", "aitken", "iqn-ils",
              "iqn-ils mixing", "explicit", "windows", "max_iterations",
              "smallest_diverging_omega", "measured_over_predicted")
#: --smoke: the options it sets (one omega each side of the measured bound, 0.07-0.1)
SMOKE = dict(omegas=[0.07, 0.2], windows=1, max_iterations=150, explicit_windows=2,
             mixings=[0.1])
EXPLICIT_GROWTH = 100.0
"""The explicit run has diverged when its largest node speed exceeds the implicit run's by
this factor (-)."""


def predicted_bound() -> dict:
    m = MEMBRANE_DENSITY * MEMBRANE_THICKNESS
    added = WATER_DENSITY * TANK_RADIUS
    return dict(membrane_mass_per_area=m, added_mass_per_area=added, mass_ratio=m / added,
                omega_max=2 * m / (m + added))


def run_case(coupling: dict, windows: int) -> dict:
    """The bundled diaphragm-fill's first ``windows`` windows with ``coupling`` keys set."""
    setup = build(load_scene("diaphragm-fill").with_keys(
        {"coupling": coupling, "dynamics": {"end_time": windows * 0.002,
                                            "frame_interval": windows}}))
    t0 = time.perf_counter()
    result = PROCEDURES["coupled-fill"](setup, lambda f, m: None)
    w = result.groups.get("windows", {})
    done = len(w.get("time", []))
    frames = result.groups["frames"]
    failure = result.attrs["failure"]
    found = re.search(r"'interface_pressure': ([0-9.eE+-]+|nan|inf)", failure)
    residual = float(found.group(1)) if found else (np.inf if failure else 0.0)
    converged = failure == "" and done == windows
    return dict(
        converged=converged,
        status="converged" if converged else ("diverged" if not residual < 1.0
                                              else "not converged"),
        last_pressure_residual=residual,
        windows_done=done, failure=result.attrs["failure"][:160],
        mean_iterations=float(np.mean(w["coupling_iterations"])) if done else None,
        iterations=[int(i) for i in w.get("coupling_iterations", [])],
        node_speed_max=float(np.nanmax(frames["node_speed_max"])),
        seconds=time.perf_counter() - t0)


def plot(result: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.2))
    rows = result["constant"]
    for r in rows:
        ok = r["converged"]
        style = {"converged": ("o", "tab:green"), "not converged": ("s", "tab:orange"),
                 "diverged": ("x", "tab:red")}[r["status"]]
        ax.plot(r["omega"], r["mean_iterations"] if ok else result["max_iterations"],
                style[0], color=style[1], ms=8)
    ax.axvline(result["predicted"]["omega_max"], color="k", ls="--",
               label=f"predicted omega_max = {result['predicted']['omega_max']:.4f}")
    for name, color in (("aitken", "tab:blue"), ("iqn-ils", "tab:purple")):
        r = result[name]
        if r["converged"]:
            ax.axhline(r["mean_iterations"], color=color, lw=1,
                       label=f"{name}: {r['mean_iterations']:.1f} iterations per window")
    for r, style in zip(result["iqn-ils mixing"], (":", "-.", (0, (1, 3)), (0, (5, 5)))):
        if r["converged"]:
            ax.axhline(r["mean_iterations"], color="tab:purple", lw=1, ls=style,
                       label=f"iqn-ils, mixing {r['mixing']:g}: {r['mean_iterations']:.1f}")
    ax.set_xscale("log")
    ax.set_xlabel("constant under-relaxation omega")
    ax.set_ylabel("mean iterations per window\n(square: not converged, x: diverged)")
    ax.set_title("Table 4.1 diaphragm, N = 14, 16$^3$, windows of 2 ms")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, which="both")
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--omegas", type=float, nargs="+",
                        default=[0.01, 0.03, 0.05, 0.07, 0.1, 0.2, 0.4, 1.0])
    parser.add_argument("--windows", type=int, default=3)
    parser.add_argument("--max-iterations", type=int, default=300)
    parser.add_argument("--explicit-windows", type=int, default=25)
    parser.add_argument("--mixings", type=float, nargs="*", default=[0.3, 0.1, 0.03])
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    if args.smoke:
        vars(args).update(SMOKE)
    output = output_dir(args.smoke)
    logging.getLogger().setLevel(logging.ERROR)
    common = dict(max_iterations=args.max_iterations, on_max_iterations="error")
    result = dict(predicted=predicted_bound(), windows=args.windows,
                  max_iterations=args.max_iterations, constant=[])
    for omega in args.omegas:
        r = run_case(dict(common, acceleration="constant", relaxation=omega), args.windows)
        result["constant"].append(dict(omega=omega, **r))
        print(f"omega {omega}: converged {r['converged']}, {r['mean_iterations']} it, "
              f"{r['seconds']:.1f} s", file=sys.stderr)
    stable = [r["omega"] for r in result["constant"] if r["converged"]]
    unstable = [r["omega"] for r in result["constant"] if r["status"] == "diverged"]
    result["largest_converging_omega"] = max(stable) if stable else None
    result["smallest_diverging_omega"] = min(unstable) if unstable else None
    result["measured_over_predicted"] = (result["largest_converging_omega"]
                                         / result["predicted"]["omega_max"]
                                         if stable else None)
    for name in ("aitken", "iqn-ils"):
        result[name] = run_case(dict(common, acceleration=name), args.windows)
    result["iqn-ils mixing"] = [
        dict(mixing=beta, **run_case(dict(common, acceleration="iqn-ils", mixing=beta),
                                     args.windows)) for beta in args.mixings]
    result["explicit"] = run_case(dict(scheme="explicit"), args.explicit_windows)
    # the explicit scheme "converges" by construction (one pass per window): it fails by
    # growth, measured as its largest node speed over the implicit run's
    result["explicit"]["speed_over_implicit"] = (result["explicit"]["node_speed_max"]
                                                 / result["iqn-ils"]["node_speed_max"])
    result["explicit"]["status"] = ("diverged" if result["explicit"]["speed_over_implicit"]
                                    > EXPLICIT_GROWTH else "stable")
    output.mkdir(parents=True, exist_ok=True)
    (output / "diaphragm_stability.json").write_text(json.dumps(result, indent=1))
    plot(result, output / "diaphragm_stability.png")
    emit("diaphragm_stability", result, args.smoke)
    return 0


if __name__ == "__main__":
    sys.exit(main())
