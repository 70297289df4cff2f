"""Grid locking map of the thesis particle membrane: strain limit x grid size.

The case (what is measured per point, when a point is locked): :mod:`cases.grid_locking`.

    python benchmarks/grid_locking.py [--grids 14 20 26 38] [--limits 0.5 1 2 5]
                                      [--end-time 0.5] [--hold 0.5] [--dt 1e-4]
                                      [--no-check] [--extra-check N LIMIT FACTOR] [--smoke]

Quasi-static check: every point is run again at twice the ramp time (columns ``fraction_2x``,
``status_2x``, ``quasi_static`` = the two fills within QS_TOL); ``--no-check`` skips it.
``--extra-check N LIMIT FACTOR`` (default 26 1 4) runs single points at FACTOR x the ramp time
(``grid_locking_check.csv``). The ramp-up is not dynamics in the physical sense: with the
thesis's SteadyState the velocity is never corrected for the constraint moves, so the reported
node speeds (10-30 m/s) are an integrated force, not motion; what matters is whether the end
state depends on the ramp time.

Writes ``benchmarks/output/grid_locking.csv`` (one row per N x limit: grid_size, error_limit,
inverted_fraction, strain_mean, seconds, status, then the columns above), ``grid_locking.png``
(map of inverted fraction over limit and N, locked and failed points marked, both ramp times)
and ``grid_locking_check.csv``; prints progress to stderr and one JSON object to stdout (a full
run also to ``docs/data/grid_locking.json``). Whole default run: about 8.5 min on 2 cores
(N = 38 at 0.5 % is 40 % of it). ``--smoke``: :data:`SMOKE` (N = 6 and 8, two limits, a 10 ms
ramp; its files under ``benchmarks/output/smoke/``).
"""
from __future__ import annotations

import argparse
import csv
import logging
import sys
import time
from pathlib import Path

import numpy as np

from _report import SMOKE_HELP, emit, output_dir
from cases.grid_locking import LOCK_RATIO, classify, locked, run_point, static_cap

#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("reference", "static_cap", "table", "quasi_static", "extra_checks",
              "total_seconds")
#: --smoke: the options it sets
SMOKE = dict(grids=[6, 8], limits=[1.0, 5.0], end_time=0.01, hold=0.005, dt=1e-4,
             no_check=False, extra_check=[[6, 1.0, 2.0]])
QS_TOL = 0.05
"""A point is quasi-static when the run at twice the ramp time ends within this fill (-)."""


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grids", type=int, nargs="+", default=[14, 20, 26, 38])
    parser.add_argument("--limits", type=float, nargs="+", default=[0.5, 1.0, 2.0, 5.0],
                        help="strain limits, thesis ErrorLimit (%%)")
    parser.add_argument("--end-time", type=float, default=0.5, help="ramp time (s)")
    parser.add_argument("--hold", type=float, default=0.5, help="longest hold at +1.05 R (s)")
    parser.add_argument("--dt", type=float, default=1e-4, help="time step (s)")
    parser.add_argument("--no-check", action="store_true",
                        help="skip the quasi-static check (every point again at 2x the ramp time)")
    parser.add_argument("--extra-check", type=float, nargs=3, action="append",
                        metavar=("N", "LIMIT", "FACTOR"),
                        help="also run grid N at LIMIT %% with FACTOR x the ramp time "
                             "(repeatable; default 26 1 4)")
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    if args.smoke:
        vars(args).update(SMOKE)
    output = output_dir(args.smoke)
    grids, limits = sorted(args.grids), sorted(args.limits)
    extra = args.extra_check if args.extra_check is not None else [[26, 1.0, 4.0]]
    logging.getLogger("fsi").setLevel(logging.ERROR)
    t_total = time.perf_counter()
    run_point(6, 1.0, 0.002, 0.0, 1e-4)  # compile the kernels
    caps = {}
    for n in sorted(set(grids) | {int(e[0]) for e in extra}):
        caps[n] = static_cap(n)
        print(f"N = {n}: static cap (fully inverted equilibrium) {caps[n]:.3f}",
              file=sys.stderr, flush=True)
    rows = []
    factors = (1.0,) if args.no_check else (1.0, 2.0)
    for factor in factors:
        for n in grids:
            for limit in limits:
                row = run_point(n, limit, factor * args.end_time, args.hold, args.dt)
                _progress(row)
                if factor == 1.0:
                    rows.append(row)
                    continue
                base = next(r for r in rows if r["grid_size"] == n and r["error_limit"] == limit)
                base.update(fraction_2x=row["inverted_fraction"], strain_mean_2x=row["strain_mean"],
                            seconds_2x=row["seconds"], status_2x=row["status"],
                            quasi_static=bool(abs(row["inverted_fraction"]
                                                  - base["inverted_fraction"]) <= QS_TOL))
    reference = classify(rows, caps)
    checks = []
    for n, limit, factor in extra:
        row = run_point(int(n), limit, factor * args.end_time, args.hold, args.dt)
        _progress(row)
        row["static_cap"] = caps[int(n)]
        row["cap_normalised"] = row["inverted_fraction"] / row["static_cap"]
        if row["status"] != "courant-error":
            row["status"] = "locked" if locked(row, reference["cap_normalised"]) else "inverted"
        checks.append(row)
    output.mkdir(parents=True, exist_ok=True)
    _write_csv(output / "grid_locking.csv", rows)
    if checks:
        _write_csv(output / "grid_locking_check.csv", checks)
    _plot(rows, grids, limits, args, output / "grid_locking.png")
    total = time.perf_counter() - t_total
    columns = ("grid_size", "error_limit", "inverted_fraction", "strain_mean", "seconds",
               "status", "ramp_end_fraction", "cap_normalised", "settled", "fraction_2x",
               "status_2x", "quasi_static")
    out = {"ramp_time_s": args.end_time, "max_hold_s": args.hold, "dt_s": args.dt,
           "lock_ratio": LOCK_RATIO, "quasi_static_tolerance": QS_TOL, "reference": reference,
           "static_cap": {str(n): caps[n] for n in grids},
           "table": [{c: r[c] for c in columns if c in r} for r in rows],
           "quasi_static": {
               "points_within_tolerance": sum(bool(r.get("quasi_static")) for r in rows),
               "points_checked": sum("quasi_static" in r for r in rows),
               "same_status": sum(r.get("status_2x") == r["status"] for r in rows)},
           "extra_checks": [{c: r[c] for c in ("grid_size", "error_limit", "ramp_time",
                                               "inverted_fraction", "strain_mean", "status",
                                               "seconds")} for r in checks],
           "total_seconds": total}
    print(f"total {total:.0f} s", file=sys.stderr, flush=True)
    emit("grid_locking", out, args.smoke)
    return out


def _progress(row: dict) -> None:
    print(f"N = {row['grid_size']:2d}, limit {row['error_limit']:g} %, "
          f"ramp {row['ramp_time']:g} s: "
          f"fill {row['inverted_fraction']:.3f} (ramp end {row['ramp_end_fraction']:.3f}), "
          f"strain {row['strain_mean']:.4f}, {row['seconds']:.1f} s, {row['status']}",
          file=sys.stderr, flush=True)


def _write_csv(path: Path, rows: list[dict]) -> None:
    fields = ["grid_size", "error_limit", "inverted_fraction", "strain_mean", "seconds",
              "status"]
    fields += [k for k in rows[0] if k not in fields]
    with open(path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=fields)
        writer.writeheader()
        for r in rows:
            writer.writerow({k: r.get(k, "") for k in fields})


def _plot(rows, grids, limits, args, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    marks = {"locked": " L", "courant-error": " C", "inverted": ""}
    grid = np.full((len(grids), len(limits)), np.nan)
    for r in rows:
        grid[grids.index(r["grid_size"]), limits.index(r["error_limit"])] = r["inverted_fraction"]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 5))
    im = ax.imshow(grid, origin="lower", cmap="viridis", vmin=0.0, vmax=1.0, aspect="auto")
    ax.set_xticks(range(len(limits)), [f"{v:g}" for v in limits])
    ax.set_yticks(range(len(grids)), [str(n) for n in grids])
    ax.set_xlabel("strain limit ErrorLimit (%)")
    ax.set_ylabel("grid size N")
    for r in rows:
        i, j = grids.index(r["grid_size"]), limits.index(r["error_limit"])
        text = f"{r['inverted_fraction']:.2f}{marks[r['status']]}"
        if "fraction_2x" in r:
            text += f"\n2x: {r['fraction_2x']:.2f}{marks[r['status_2x']]}"
        ax.text(j, i, text, ha="center", va="center", fontsize=9,
                color="w" if r["inverted_fraction"] < 0.5 else "k",
                fontweight="bold" if r["status"] != "inverted" else "normal")
    fig.colorbar(im, ax=ax, label="inverted fraction (of the mirrored rest volume)")
    ax.set_title(f"ramp {args.end_time:g} s (2x: {2 * args.end_time:g} s) + hold; "
                 "L locked, C Courant error", fontsize=10)
    for n in grids:
        sel = sorted((r for r in rows if r["grid_size"] == n), key=lambda r: r["error_limit"])
        x = [r["error_limit"] for r in sel]
        line, = bx.plot(x, [r["inverted_fraction"] for r in sel], "o-", label=f"N = {n}")
        color = line.get_color()
        if all("fraction_2x" in r for r in sel):
            bx.plot(x, [r["fraction_2x"] for r in sel], "o--", mfc="none", color=color, lw=1)
        for r in sel:
            for key, status in (("inverted_fraction", "status"), ("fraction_2x", "status_2x")):
                if key not in r:
                    continue
                if r[status] == "locked":
                    bx.plot(r["error_limit"], r[key], "x", ms=11, color="k")
                elif r[status] == "courant-error":
                    bx.plot(r["error_limit"], r[key], "s", ms=11, mfc="none", color="r")
        bx.axhline(sel[0]["static_cap"], color=color, ls=":", lw=1)
    bx.plot([], [], "o--", mfc="none", color="gray", lw=1, label="2x ramp time")
    bx.plot([], [], "x", color="k", label="locked")
    bx.plot([], [], "s", mfc="none", color="r", label="Courant error")
    bx.plot([], [], ":", color="gray", label="static full inversion of N (cap)")
    bx.set_xscale("log")
    bx.set_xticks(limits, [f"{v:g}" for v in limits])
    bx.minorticks_off()
    bx.set_xlabel("strain limit ErrorLimit (%)")
    bx.set_ylabel("inverted fraction (of the mirrored rest volume)")
    bx.set_ylim(0, 1)
    bx.grid(True, alpha=0.3)
    bx.legend(fontsize=8, loc="lower right")
    bx.set_title(f"thesis stepper, dt {args.dt:g} s; locked: fill/cap < {LOCK_RATIO:g} x "
                 "reference's", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    main()
