"""The rigid sphere's pendulum parameters by tank fraction from SLOSH-ML's algorithm, beside
this project's reference and its modes rung.

    python benchmarks/slosh_ml_compare.py --slosh-py DIR [--fills 0.1 0.3 ...]
                                          [--nsteps 400 800] [--smoke]

SLOSH-ML (github.com/LGST-LAB/slosh_ml) is the open tool guidance engineers use for the
slosh pendulums of axisymmetric tanks: Lomen's Ritz method of NASA CR-230 as updated by Dodge
(SwRI 2000), Bessel-function trial potentials about the liquid's centre of mass. Its public
release is a Windows executable and MATLAB source; Slosh-PY
(github.com/chairmanmao256/Slosh-PY, commit PINNED_COMMIT) is its line-by-line Python port,
which this script imports unchanged from ``DIR``, a checkout of that commit:

    git clone https://github.com/chairmanmao256/Slosh-PY DIR
    git -C DIR checkout c060f8a

The port has no licence file, so it is not redistributed here. Conventions converted:

- its fill ratio is by height, h / (2R); the tank fraction V / (4/3 pi R^3) is solved for h;
- its lambda_k is omega^2 a / g with a the surface radius; lambda = omega^2 R / g = R / L_k;
- its heights are from the tank bottom; here they are from the tank centre (+ up);
- the contour is the exact circle r = sqrt(z (2R - z)), substituted for a tabulated one.

Per fill, at each ``--nsteps`` (its quadrature's steps; N = 10 Bessel orders, M = 5 depth
terms, its defaults): lambda1, the first slosh mass fraction m1 / M, the pendulum hinge
height and the first mode's slosh-mass height; ``digits`` is the change from the coarsest to
the finest ``--nsteps`` (what its value is good to), and ``vs_reference`` the finest value's
relative difference from ``docs/data/sphere_slosh_reference.json`` (isoparametric P2, 8
digits) and ``vs_modes`` from ``docs/data/modes_by_fill.json`` (the modes rung on its default
grid). A full run writes ``docs/data/slosh_ml_compare.json`` and a PNG. ``--smoke`` without
``--slosh-py`` cannot run the port (CI has no copy of it): it recomputes the comparison
columns from the stored ``docs/data/slosh_ml_compare.json`` and the current reference, so
that a changed reference shows; with ``--slosh-py`` it runs tank fraction 0.5 at nsteps 50.
"""
from __future__ import annotations

import argparse
import contextlib
import hashlib
import io
import json
import os
import sys
import time
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from _report import DOCS_DATA, SMOKE_HELP, emit, output_dir

PINNED_COMMIT = "c060f8a836d37522c3849d2ff93fa3e5dc90b225"
PINNED_BLOBS = {"Slosh.py": "198a0d20e06ae225adad622d0a676460cecf80b7",
                "SloshFunc.py": "ec3647dc4b6d9e83b801e3ad4f37bf06def56a40"}
"""The port's two modules at PINNED_COMMIT, as git blob hashes (checked on any copy, a git
checkout or not)."""
FILLS = (0.1, 0.3, 0.5, 0.6, 0.7, 0.8, 0.9)
NSTEPS = (400, 800)
BESSEL_ORDERS = 10
"""N: the trial potentials' Bessel orders (the port's default)."""
DEPTH_TERMS = 5
"""M: the trial potentials' depth terms (the port's default)."""
DOC_FIELDS = ("rows", "tool", "tool_ran")
QUANTITIES = ("lambda1", "slosh_mass_fraction", "hinge_height", "slosh_mass_height")


def depth_from_fraction(fraction: float, radius: float = 1.0) -> float:
    """Liquid depth h (m) in a sphere of ``radius`` (m) at tank fraction V / (4/3 pi R^3)."""
    volume = fraction * 4.0 / 3.0 * np.pi * radius ** 3
    return brentq(lambda h: np.pi * h * h * (3 * radius - h) / 3 - volume, 0.0, 2 * radius,
                  xtol=1e-15)


def blob_hash(path: Path) -> str:
    """The git blob hash of the file at ``path`` (sha1 of 'blob <size>\\0' + its bytes)."""
    data = path.read_bytes()
    return hashlib.sha1(b"blob %d\0" % len(data) + data).hexdigest()


def changed_modules(directory: Path) -> list[str]:
    """The port's modules in ``directory`` that differ from PINNED_BLOBS (or are missing)."""
    return [name for name, blob in PINNED_BLOBS.items()
            if not (directory / name).exists() or blob_hash(directory / name) != blob]


def run_port(directory: Path, fraction: float, nsteps: int, work: Path) -> dict:
    """The port's first mode at ``fraction`` (R = g = rho = 1), in this project's conventions."""
    if str(directory) not in sys.path:
        sys.path.insert(0, str(directory))
    import matplotlib
    matplotlib.use("Agg")
    from Slosh import Tank  # the port, unchanged

    settings = work / f"settings_{nsteps}.txt"
    settings.write_text(f"N: {BESSEL_ORDERS}\nM: {DEPTH_TERMS}\nnsteps: {nsteps}\nnmodes: 3\n"
                        "SpringModeSpinner: 3\ng: 1.0\nrho: 1.0\n")
    contour = work / "sphere.txt"      # read by the constructor, then replaced by the circle
    z = np.linspace(0.0, 2.0, 201)
    r = np.sqrt(np.clip(z * (2.0 - z), 0.0, None))
    np.savetxt(contour, np.column_stack([z, 0 * z, z, r]), delimiter=",")
    depth = depth_from_fraction(fraction)
    started = time.perf_counter()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        tank = Tank(depth / 2.0, fname=str(contour), settings=str(settings), delimiter=",")
        tank.OC_original = lambda zz: np.sqrt(np.clip(zz * (2.0 - zz), 0.0, None))
        tank.IC_original = lambda zz: 0.0 * np.asarray(zz, dtype=float)
        tank.z_oc_original = np.array([0.0, 1.0, 2.0])
        tank.z_ic_original = np.array([0.0, 2.0])
        tank.get_geometry(depth / 2.0)
        tank.calculate()
    seconds = time.perf_counter() - started
    length = np.asarray(tank.L_k[1:], dtype=float)
    mass = np.asarray(tank.M_k[1:], dtype=float) / tank.fluid_volume
    hinge = np.asarray(tank.H_k[1:], dtype=float) - 1.0
    mass_height = np.asarray(tank.H_k_spring[1:], dtype=float) - 1.0
    physical = np.flatnonzero((length > 0) & np.isfinite(length) & np.isfinite(mass))
    first = physical[np.argmax(length[physical])]          # the lowest omega^2 = g / L
    return {"lambda1": float(1.0 / length[first]),
            "slosh_mass_fraction": float(mass[first]),
            "hinge_height": float(hinge[first]),
            "slosh_mass_height": float(mass_height[first]),
            "volume_error": float(tank.fluid_volume / (fraction * 4 / 3 * np.pi) - 1.0),
            "seconds": round(seconds, 1)}


def reference_values() -> tuple[dict, dict]:
    """lambda1 and m1 / M by fill: the P2 reference's, and the modes rung's on its default
    grid (each {fill string: {quantity: value}}; empty when its file is absent)."""
    reference, modes = {}, {}
    path = DOCS_DATA / "sphere_slosh_reference.json"
    if path.exists():
        for key, row in json.loads(path.read_text())["fills"].items():
            reference[f"{float(key):.1f}"] = {"lambda1": row["lambda1"],
                                              "slosh_mass_fraction": row["slosh_mass_fraction"]}
    path = DOCS_DATA / "modes_by_fill.json"
    if path.exists():
        data = json.loads(path.read_text())
        finest = max(case["cells"] for case in data["cases"]) if data["cases"] else None
        default = 24 if any(c["cells"] == 24 for c in data["cases"]) else finest
        for case in data["cases"]:
            if case["cells"] == default:
                modes[f"{case['fill']:.1f}"] = {
                    "lambda1": case["lambda1"],
                    "slosh_mass_fraction": case["slosh_mass_fraction"]}
    return reference, modes


def compare(row: dict, reference: dict, modes: dict) -> dict:
    """``row`` with its relative differences from the reference and the modes rung."""
    key = f"{row['fill']:.1f}"
    out = dict(row)
    for name, table in (("vs_reference", reference), ("vs_modes", modes)):
        peer = table.get(key, {})
        out[name] = {q: row["finest"][q] / peer[q] - 1.0 for q in ("lambda1", "slosh_mass_fraction")
                     if q in peer}
    # a sphere's pendulums all hinge at its centre (the pressure resultant passes through it)
    out["vs_reference"]["hinge_height"] = row["finest"]["hinge_height"]
    return out


def plot(rows: list, reference: dict, modes: dict, figure: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, dx) = plt.subplots(1, 2, figsize=(10, 4))
    fills = sorted(float(k) for k in reference)
    ax.plot(fills, [reference[f"{f:.1f}"]["lambda1"] for f in fills], "k-",
            label="P2 reference (8 digits)")
    if modes:
        mf = sorted(float(k) for k in modes)
        ax.plot(mf, [modes[f"{f:.1f}"]["lambda1"] for f in mf], "o", mfc="none",
                label="modes rung, 24$^3$")
    ax.plot([r["fill"] for r in rows], [r["finest"]["lambda1"] for r in rows], "s",
            label="SLOSH-ML (Slosh-PY)")
    ax.set_xlabel("tank fraction V / (4/3 $\\pi$ R$^3$)")
    ax.set_ylabel("$\\lambda_1 = \\omega^2 R / g$")
    ax.legend()
    for name, marker, label in (("vs_reference", "s", "SLOSH-ML"),):
        dx.plot([r["fill"] for r in rows], [100 * r[name].get("lambda1", np.nan) for r in rows],
                marker, label=f"{label} $\\lambda_1$")
        dx.plot([r["fill"] for r in rows],
                [100 * r[name].get("slosh_mass_fraction", np.nan) for r in rows],
                marker, mfc="none", label=f"{label} $m_1/M$")
    if modes:
        keys = sorted(float(k) for k in modes if k in reference)
        dx.plot(keys, [100 * (modes[f"{f:.1f}"]["lambda1"] / reference[f"{f:.1f}"]["lambda1"] - 1)
                       for f in keys], "o", mfc="none", label="modes rung 24$^3$ $\\lambda_1$")
    dx.axhline(0, color="k", lw=0.5)
    dx.set_xlabel("tank fraction")
    dx.set_ylabel("difference from the P2 reference (%)")
    dx.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(figure, dpi=120)
    plt.close(fig)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--slosh-py", type=Path, default=os.environ.get("SLOSH_PY"),
                        help="a checkout of Slosh-PY at commit %s" % PINNED_COMMIT[:7])
    parser.add_argument("--fills", type=float, nargs="+", default=list(FILLS))
    parser.add_argument("--nsteps", type=int, nargs="+", default=list(NSTEPS))
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args()
    reference, modes = reference_values()
    tool = {"name": "Slosh-PY", "repo": "chairmanmao256/Slosh-PY", "pinned": PINNED_COMMIT,
            "algorithm": "SLOSH-ML (LGST-LAB/slosh_ml), Lomen NASA CR-230 / Dodge 2000",
            "bessel_orders": BESSEL_ORDERS, "depth_terms": DEPTH_TERMS}
    if args.slosh_py is None:
        if not args.smoke:
            sys.stderr.write("slosh_ml_compare: --slosh-py DIR (a checkout of Slosh-PY at "
                             f"{PINNED_COMMIT[:7]}) is required for a full run\n")
            return 2
        stored = json.loads((DOCS_DATA / "slosh_ml_compare.json").read_text())
        rows = [compare({k: r[k] for k in ("fill", "depth", "runs", "finest", "digits")},
                        reference, modes) for r in stored["rows"]]
        emit("slosh_ml_compare", {"rows": rows, "tool": stored["tool"], "tool_ran": False},
             smoke=True)
        return 0
    directory = args.slosh_py.resolve()
    changed = changed_modules(directory)
    if changed:
        sys.stderr.write(f"slosh_ml_compare: --slosh-py {directory}: {', '.join(changed)} "
                         f"missing or not as at Slosh-PY {PINNED_COMMIT[:7]}\n")
        return 2
    tool["modules"] = PINNED_BLOBS
    fills = [0.5] if args.smoke else args.fills
    nsteps = [50] if args.smoke else sorted(args.nsteps)
    work = output_dir(args.smoke) / "slosh_ml"
    work.mkdir(parents=True, exist_ok=True)
    rows = []
    for fill in fills:
        runs = {str(n): run_port(directory, fill, n, work) for n in nsteps}
        finest = runs[str(nsteps[-1])]
        coarsest = runs[str(nsteps[0])]
        row = {"fill": fill, "depth": depth_from_fraction(fill), "runs": runs,
               "finest": {q: finest[q] for q in QUANTITIES},
               "digits": {q: abs(finest[q] - coarsest[q]) for q in QUANTITIES}}
        rows.append(compare(row, reference, modes))
        print(f"fill {fill}: lambda1 {finest['lambda1']:.5f} "
              f"({100 * rows[-1]['vs_reference'].get('lambda1', np.nan):+.2f} % vs reference)",
              file=sys.stderr, flush=True)
    if not args.smoke:
        plot(rows, reference, modes, output_dir(False) / "slosh_ml_compare.png")
    emit("slosh_ml_compare", {"rows": rows, "tool": tool, "tool_ran": True}, args.smoke)
    return 0


if __name__ == "__main__":
    sys.exit(main())
