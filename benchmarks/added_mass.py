"""The added-mass stability map of partitioned coupling (Causin, Gerbeau & Nobile 2005): the
case of :mod:`cases.added_mass` (model, theory and parameters in its docstring) swept over the
mass ratio q = rho_f mu_max / (rho_s h).

    python benchmarks/added_mass.py [--smoke]

Writes ``benchmarks/output/added_mass_stability.png`` (constant-relaxation map against the
bound omega_max, explicit growth per window, Aitken and IQN-ILS iterations) and prints one JSON
object (also written to ``docs/data/added_mass.json``). ``--smoke``: two sampled mass ratios, a
3 x 4 map, three explicit and two accelerated cases (the figure under
``benchmarks/output/smoke/``, nothing in ``docs/data``).
"""
from __future__ import annotations

import argparse
import logging
import time
from dataclasses import asdict
from pathlib import Path

import numpy as np

from _report import SMOKE_HELP, emit, output_dir
from cases.added_mass import (REFERENCE, Problem, accelerated_run, constant_map, explicit_run,
                              largest_stable_omega)

FIGURE_NAME = "added_mass_stability.png"
GOALS = {"omega_max_relative_difference": 0.10}
#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("goals", "constant_map_cells", "constant_map_cells_contradicting_bound",
              "accelerated", "per_mass_ratio", "seconds")


def plot(problem, ratios, omegas, cmap_data, sampled, explicit, accelerated, path: Path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap

    fig, axes = plt.subplots(2, 2, figsize=(12, 9), constrained_layout=True)
    qq = np.geomspace(min(ratios), max(ratios), 200)
    bound = 2.0 / (1.0 + qq)  # 2 m / (m + rho_f mu_max)

    ax = axes[0, 0]
    its = np.where(cmap_data > 0, cmap_data, np.nan)
    mesh = ax.pcolormesh(ratios, omegas, its, shading="nearest", cmap="viridis",
                         norm=matplotlib.colors.LogNorm(vmin=max(1, np.nanmin(its)),
                                                        vmax=np.nanmax(its)))
    fail = np.where(cmap_data <= 0, cmap_data, np.nan)
    ax.pcolormesh(ratios, omegas, fail, shading="nearest",
                  cmap=ListedColormap(["#d62728", "#bbbbbb"]), vmin=-1, vmax=0)
    ax.plot(qq, bound, "k-", lw=2, label=r"theory $2\rho_sh/(\rho_sh+\rho_f\mu_{max})$")
    ax.plot([s["mass_ratio"] for s in sampled], [s["omega_max_measured"] for s in sampled],
            "wo", mec="k", label="measured largest stable omega (bisection)")
    ax.set(xscale="log", ylim=(0, max(omegas) + 0.025),
           xlabel=r"mass ratio $\rho_f\mu_{max}/(\rho_sh)$", ylabel=r"relaxation $\omega$",
           title="implicit-serial, constant relaxation (window 1)\n"
                 "colour: iterations; red: diverged; grey: not converged in 200")
    fig.colorbar(mesh, ax=ax, label="iterations to 1e-8", pad=0.01)
    ax.legend(loc="upper right", fontsize=8)

    ax = axes[0, 1]
    q_e = np.array([e["mass_ratio"] for e in explicit])
    growth = np.array([e["growth_per_window"] for e in explicit])
    div = np.array([e["diverged"] for e in explicit])
    ax.loglog(qq, [problem.with_mass_ratio(q).explicit_spectral_radius for q in qq], "k-",
              lw=1, label="theory: spectral radius (largest |z|)")
    ax.loglog(q_e[~div], growth[~div], "o", color="tab:green", label="measured: stable")
    ax.loglog(q_e[div], growth[div], "x", color="tab:red", ms=8, label="measured: diverged")
    ax.axvline(problem.explicit_critical_mass_ratio, color="k", ls="--", lw=2,
               label=r"theory: unstable for $q > 1 + k\,\Delta t^2/(4\rho_sh)$")
    ax.axhline(1.0, color="gray", ls=":")
    ax.set(xlabel=r"mass ratio $\rho_f\mu_{max}/(\rho_sh)$",
           ylabel="growth per window of the pressure's 2nd difference",
           title="explicit (staggered), backward Euler, 1000 windows")
    ax.legend(fontsize=8)

    for ax, name in ((axes[1, 0], "aitken"), (axes[1, 1], "iqn-ils")):
        rows = accelerated[name]
        q_a = np.array([r["mass_ratio"] for r in rows])
        ok = np.array([r["converged"] for r in rows])
        mean = np.array([r["mean_iterations"] for r in rows])
        mx = np.array([r["max_iterations"] for r in rows])
        ax.semilogx(q_a[ok], mean[ok], "o-", color="tab:blue", label="mean iterations / window")
        ax.semilogx(q_a[ok], mx[ok], "s--", color="tab:orange", ms=4,
                    label="max iterations / window")
        if (~ok).any():
            ax.semilogx(q_a[~ok], np.full((~ok).sum(), 1.0), "x", color="tab:red", ms=10,
                        label="not converged")
        ax.set(xlabel=r"mass ratio $\rho_f\mu_{max}/(\rho_sh)$", ylabel="iterations",
               ylim=(0, None),
               title=f"implicit-serial, {name}: converged at {ok.sum()}/{ok.size} mass ratios")
        ax.legend(fontsize=8)
    fig.suptitle(f"Added-mass model problem (Causin, Gerbeau & Nobile 2005): L = "
                 f"{problem.length} m, R = {problem.height} m, k = {problem.stiffness:g} Pa/m, "
                 f"dt = {problem.dt:g} s, N = {problem.n_nodes}, tol = 1e-8")
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    figure = output_dir(args.smoke) / FIGURE_NAME
    logging.getLogger("coupling").setLevel(logging.ERROR)  # the map accepts diverged windows
    t0 = time.perf_counter()
    problem = Problem()
    if args.smoke:
        sampled_q = np.array([0.5, 50.0])
        map_q = np.geomspace(0.1, 100.0, 3)
        omegas = np.array([0.05, 0.5, 1.0, 1.2])
        explicit_q = np.array([0.5, 1.05, 10.0])
    else:
        sampled_q = np.geomspace(0.1, 100.0, 8)  # avoids q = 1, the explicit scheme's edge
        map_q = np.geomspace(0.1, 100.0, 24)
        omegas = np.arange(0.05, 1.2001, 0.05)
        explicit_q = np.unique(np.concatenate([np.geomspace(0.1, 100.0, 24),
                                               [0.9, 0.95, 1.05, 1.1]]))
    accelerated_q = map_q[[0, -1]] if args.smoke else map_q

    sampled = []
    for q in sampled_q:
        pq = problem.with_mass_ratio(q)
        measured = largest_stable_omega(pq)
        e = explicit_run(pq)
        theory_diverges = bool(pq.mass_ratio > pq.explicit_critical_mass_ratio)
        sampled.append({
            "mass_ratio": float(q), "wall_mass_per_area_kg_m2": pq.mass, "beta": pq.beta,
            "omega_max_measured": measured, "omega_max_predicted": pq.omega_max,
            "relative_difference": (measured - pq.omega_max) / pq.omega_max,
            "omega_max_discrete_exact": pq.omega_max_discrete,
            "omega_max_expected_500_iterations": pq.omega_max_finite_iterations(500, 1e-8),
            "explicit_theory_diverges": theory_diverges,
            "explicit_diverged": e["diverged"],
            "explicit_as_theory": e["diverged"] == theory_diverges,
            "explicit_growth_per_window": e["growth_per_window"],
            "explicit_spectral_radius_theory": pq.explicit_spectral_radius})

    explicit = []
    for q in explicit_q:
        pq = problem.with_mass_ratio(q)
        e = explicit_run(pq)
        explicit.append({"mass_ratio": float(q), **e,
                         "theory_diverges": bool(pq.mass_ratio
                                                 > pq.explicit_critical_mass_ratio)})

    accelerated = {name: [{"mass_ratio": float(q),
                           **accelerated_run(problem.with_mass_ratio(q), name)}
                          for q in accelerated_q]
                   for name in ("aitken", "iqn-ils")}

    cmap_data = constant_map(problem, map_q, omegas)
    # a converged map cell above the bound (or a diverged one below 0.9 of it) contradicts theory
    bound = 2.0 / (1.0 + map_q)[None, :]
    contradictions = int(np.sum((cmap_data > 0) & (omegas[:, None] > bound))
                         + np.sum((cmap_data < 0) & (omegas[:, None] < 0.9 * bound)))

    plot(problem, map_q, omegas, cmap_data, sampled, explicit, accelerated, figure)

    rel = [abs(s["relative_difference"]) for s in sampled]
    result = {
        "reference": REFERENCE,
        "problem": {**asdict(problem), "rho_s": "swept: rho_f mu_max / (q h)",
                    "mu_max_m": float(problem.mu[0]),
                    "beta_max": problem.with_mass_ratio(100.0).beta,
                    "explicit_critical_mass_ratio": problem.explicit_critical_mass_ratio},
        "settings": {"tolerance": "relative pressure change <= 1e-8",
                     "bisection": "2 windows, max_iterations 500, on_max_iterations error",
                     "explicit": "1000 windows", "aitken_iqn": "10 windows, max_iterations "
                     "100, initial_relaxation 0.1",
                     "map": f"{len(map_q)} mass ratios x {len(omegas)} omegas, 1 window, "
                            "max_iterations 200"},
        "per_mass_ratio": sampled,
        "explicit_sweep": [{k: e[k] for k in ("mass_ratio", "diverged", "theory_diverges",
                                               "growth_per_window")} for e in explicit],
        "accelerated": {name: {"converged_everywhere": all(r["converged"] for r in rows),
                               "mean_iterations_range": [
                                   min(r["mean_iterations"] for r in rows),
                                   max(r["mean_iterations"] for r in rows)],
                               "max_error_vs_monolithic": max(r["error_vs_monolithic"]
                                                              for r in rows)}
                        for name, rows in accelerated.items()},
        "constant_map_cells_contradicting_bound": contradictions,
        "constant_map_cells": {"converged": int(np.sum(cmap_data > 0)),
                               "diverged": int(np.sum(cmap_data < 0)),
                               "not_converged_in_200": int(np.sum(cmap_data == 0))},
        "goals": {
            "explicit_diverges_where_theory_says": all(
                e["diverged"] == e["theory_diverges"] for e in explicit) and all(
                s["explicit_as_theory"] for s in sampled),
            "omega_max_within_10_percent": bool(
                max(rel) <= GOALS["omega_max_relative_difference"]),
            "max_relative_difference": max(rel),
            "aitken_converges_across_map": all(r["converged"] for r in accelerated["aitken"]),
            "iqn_ils_converges_across_map": all(r["converged"]
                                                for r in accelerated["iqn-ils"])},
        "figure": str(figure.relative_to(Path(__file__).resolve().parents[1])),
        "seconds": round(time.perf_counter() - t0, 1),
    }
    emit("added_mass", result, args.smoke, allow_nan=False)
    return result


if __name__ == "__main__":
    main()
