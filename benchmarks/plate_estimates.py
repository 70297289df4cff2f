"""The analytical rung against the shell model: where each closed form of a flat clamped
diaphragm holds, and the thesis's Ch. 3 cases (Figs 3.2-3.4).

    python benchmarks/plate_estimates.py [--grid-sizes 20 26 38] [--loads-per-decade 2] [--smoke]

1. Validity.  A flat disc of the thesis's radius, thickness and E (nu = 0.5), clamped and
   held, under uniform pressures from 1 mPa to 3 kPa (w0 from 0.01 t to 25 t), solved by the
   shell model's energies (:class:`structure.plate.ShellDisc`, by load continuation) on each
   grid; every closed form's centre deflection over the finest grid's.  Reported: the largest
   w0 / t at which the linear plate is within 5 % of the shell (the thesis: t / 5), the
   large-deflection plate's largest error up to 3 t (the thesis's limit) and beyond, and the
   smallest w0 / t from which Hencky's membrane is within 5 %.  The grid error is the
   difference between the two finest grids.
2. The thesis's cases (Sec. 3.1.4): 16.5 in and 40 in tanks, tank fractions 0.25 and 0.5 of
   water on a flat equator diaphragm, t = 0.07 in (the bundled ``thesis-plate`` scene and the
   same with tank.radius = 0.508): the load, every estimate's w0, w0 / t and validity.  The
   thesis's figures are images lost from its text, so its numbers cannot be compared; its
   statements can: the deflection is far beyond the large-deflection limit of 3 t.

Writes ``benchmarks/output/plate_estimates.json`` and ``plate_estimates.png`` (each estimate
over the shell against w0 / t, the thesis's limits marked); prints one JSON object (a full run
also writes it to ``docs/data/plate_estimates.json``). Default run: about 4.5 min on 2 cores
(N = 38: 13 s per load). ``--smoke``: :data:`SMOKE` (two coarse grids, :data:`SMOKE_LOADS` loads;
its files under ``benchmarks/output/smoke/``).
3. Newton on the finest grid's same energies (:meth:`structure.plate.ShellDisc.
   newton_centre_deflections`), timed in the same run as the shell's L-BFGS, its peer:
   ``newton`` (seconds per load, the speed-up over the shell, the largest difference of w0).
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

from _report import SMOKE_HELP, emit, output_dir
from fsi.constants import (MEMBRANE_THICKNESS, MEMBRANE_YOUNGS_MODULUS, STANDARD_GRAVITY,
                           TANK_RADIUS, WATER_DENSITY)
from fsi.procedures.plate_estimate import PLATE_LOADS
from structure.plate import (ESTIMATES, LARGE_DEFLECTION_LIMIT, SMALL_DEFLECTION_LIMIT,
                             FlatDiaphragm, ShellDisc)

#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("grid_sizes", "validity", "thesis_cases", "seconds_per_load", "grid_error",
              "newton", "speed_ratio_shell_over_closed_forms")
#: --smoke: the grids and the number of loads over the same range (both sides of 3 t)
SMOKE = dict(grid_sizes=[4, 8])
SMOKE_LOADS = 4
AGREEMENT = 0.05
"""An estimate 'holds' where it is within this fraction of the shell model (-)."""
INCH = 0.0254  # m
THESIS_TANKS = {"16.5 in": 16.5 * INCH / 2, "40 in": 40 * INCH / 2}
"""Tank radii (m) of thesis Figs 3.2-3.4."""
THESIS_FILLS = (0.25, 0.5)


def shell_sweep(plate: FlatDiaphragm, grid_sizes, loads) -> dict:
    """Centre deflection (m) by grid, and the seconds per load."""
    out = {}
    for n in grid_sizes:
        t0 = time.perf_counter()
        w0 = ShellDisc.build(plate, n).centre_deflections(loads)
        out[n] = dict(w0=w0, seconds_per_load=(time.perf_counter() - t0) / len(loads))
        print(f"N = {n}: {out[n]['seconds_per_load']:.1f} s per load", file=sys.stderr)
    return out


def newton_sweep(plate: FlatDiaphragm, grid_size: int, loads, w0_shell) -> dict:
    """The same loads by Newton on the same energies and grid (the peer of the shell's
    L-BFGS in the same run): seconds per load, the ratio, and the largest relative
    difference of w0 from the shell's."""
    disc = ShellDisc.build(plate, grid_size)
    model = disc.newton_model()
    disc.newton_centre_deflections(loads[:2], model)  # compile the kernels
    t0 = time.perf_counter()
    w0, converged = disc.newton_centre_deflections(loads, model)
    seconds = (time.perf_counter() - t0) / len(loads)
    return dict(grid_size=grid_size, seconds_per_load=seconds, all_converged=converged,
                max_relative_w0_difference=float(np.max(np.abs(w0 / w0_shell - 1))))


def validity(plate: FlatDiaphragm, loads, w0_shell) -> dict:
    """Each estimate over the shell, and the measured limits."""
    depth = w0_shell / plate.thickness
    ratio = {name: np.array([e.centre(plate, q) for q in loads]) / w0_shell - 1
             for name, e in ESTIMATES.items()}
    small_ok = np.abs(ratio["small"]) <= AGREEMENT
    hencky_ok = np.abs(ratio["hencky"]) <= AGREEMENT
    k = _first_false(small_ok)  # the linear plate holds from the smallest load up to k
    j = len(depth) - _first_false(hencky_ok[::-1])  # Hencky holds from j to the largest
    within = depth <= LARGE_DEFLECTION_LIMIT
    return dict(
        depth=depth.tolist(),
        ratio={k: v.tolist() for k, v in ratio.items()},
        small_holds_to_depth=float(depth[k - 1]) if k > 0 else None,
        small_fails_at_depth=float(depth[k]) if k < len(depth) else None,
        large_max_error_within_3t=float(np.abs(ratio["large"][within]).max()),
        large_max_error_beyond_3t=float(np.abs(ratio["large"][~within]).max()),
        hencky_holds_from_depth=float(depth[j]) if j < len(depth) else None,
        hencky_fails_at_depth=float(depth[j - 1]) if j > 0 else None,
    )


def _first_false(mask: np.ndarray) -> int:
    """Index of the first False in ``mask``, or its length."""
    return int(np.argmin(mask)) if not mask.all() else len(mask)


def thesis_cases() -> list[dict]:
    rows = []
    for tank, radius in THESIS_TANKS.items():
        plate = FlatDiaphragm(radius, MEMBRANE_THICKNESS, MEMBRANE_YOUNGS_MODULUS, 0.5)
        for fill in THESIS_FILLS:
            q = PLATE_LOADS["hydrostatic"](fill, radius, WATER_DENSITY, STANDARD_GRAVITY)
            row = dict(tank=tank, radius=radius, tank_fraction=fill, pressure=q)
            for name, e in ESTIMATES.items():
                w0 = e.centre(plate, q)
                row[name] = dict(centre_deflection=w0, depth=w0 / plate.thickness,
                                 over_radius=w0 / radius, valid=bool(e.valid(plate, q)))
            rows.append(row)
    return rows


def plot(result: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    v = result["validity"]
    depth = np.array(v["depth"])
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for name, r in v["ratio"].items():
        ax.plot(depth, np.abs(r), "o-", ms=3, label=f"{name}: {ESTIMATES[name].description}")
    ax.axhline(AGREEMENT, color="k", lw=0.8, ls=":")
    for x, text in ((SMALL_DEFLECTION_LIMIT, "t/5"), (LARGE_DEFLECTION_LIMIT, "3 t")):
        ax.axvline(x, color="0.5", lw=0.8)
        ax.text(x, 1.5e-3, f" thesis {text}", fontsize=8, color="0.4")
    grid = result["grid_error"]
    ax.plot(depth, grid, "k--", lw=0.8, label="shell grid error (two finest grids)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_ylim(1e-3, 1e4)
    ax.set_xlabel("centre deflection / thickness, w0 / t (shell model)")
    ax.set_ylabel("|estimate / shell - 1|")
    ax.set_title(f"Flat clamped disc a = {TANK_RADIUS} m, t = {1e3 * MEMBRANE_THICKNESS} mm, "
                 f"nu = 0.5, shell N = {result['grid_sizes'][-1]}")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3, which="both")
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid-sizes", type=int, nargs="+", default=[20, 26, 38])
    parser.add_argument("--loads-per-decade", type=int, default=2)
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    if args.smoke:
        vars(args).update(SMOKE)
    output = output_dir(args.smoke)
    plate = FlatDiaphragm(TANK_RADIUS, MEMBRANE_THICKNESS, MEMBRANE_YOUNGS_MODULUS, 0.5)
    count = SMOKE_LOADS if args.smoke else int(round(6.5 * args.loads_per_decade)) + 1
    loads = np.logspace(-3, np.log10(3000.0), count)
    shell = shell_sweep(plate, args.grid_sizes, loads)
    finest = shell[args.grid_sizes[-1]]["w0"]
    grid_error = np.abs(shell[args.grid_sizes[-2]]["w0"] / finest - 1) \
        if len(args.grid_sizes) > 1 else np.full(len(loads), np.nan)
    newton = newton_sweep(plate, args.grid_sizes[-1], loads, finest)
    newton["speedup_over_shell"] = shell[args.grid_sizes[-1]]["seconds_per_load"] \
        / newton["seconds_per_load"]
    t0 = time.perf_counter()
    for q in loads:
        for e in ESTIMATES.values():
            e.centre(plate, q)
    closed_seconds = (time.perf_counter() - t0) / len(loads)
    result = dict(
        grid_sizes=args.grid_sizes, loads=loads.tolist(),
        shell_centre_deflection={str(n): s["w0"].tolist() for n, s in shell.items()},
        grid_error=grid_error.tolist(),
        validity=validity(plate, loads, finest),
        thesis_cases=thesis_cases(),
        seconds_per_load={"closed_forms": closed_seconds,
                          **{f"shell_N{n}": s["seconds_per_load"] for n, s in shell.items()}},
        speed_ratio_shell_over_closed_forms=shell[args.grid_sizes[-1]]["seconds_per_load"]
        / closed_seconds,
        newton=newton,
    )
    output.mkdir(parents=True, exist_ok=True)
    (output / "plate_estimates.json").write_text(json.dumps(result, indent=1))
    plot(result, output / "plate_estimates.png")
    emit("plate_estimates", result, args.smoke)
    return 0


if __name__ == "__main__":
    sys.exit(main())
