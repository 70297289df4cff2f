"""The valve fill with inertia (``valve-fill``: 1e-3 m^3/s opened in 20 ms, tank fraction
0.1 -> 0.9, 20 ms windows, IQN-ILS with mixing 0.1) against the static model at every 0.1 of
tank fraction, beside the thesis's slow fill when its result is given.

    python benchmarks/valve_fill.py [--fill DIR] [--thesis-fill DIR]

``--fill``: the result folder of ``fsi run valve-fill`` (run here when not given: about
15 min). ``--thesis-fill``: that of ``fsi run thesis-fill`` (2e-5 m^3/s, quasi-static
windows), compared the same way when given. The static references and measures are those of
``benchmarks/thesis_fill_drain.py``: the volume sweep of the same membrane model and grid,
and the static equilibrium sought from each frame's shape (the same fold state); Eqn 6.1 (%),
pressure level dynamic - static (Pa), liquid centre of mass distance (mm), and the volume
bookkeeping.

Writes ``benchmarks/output/valve_fill.json`` and ``valve_fill.png``; prints one JSON object.
"""
from __future__ import annotations

import argparse
import json
import logging
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from fsi.output import read_result  # noqa: E402
from fsi.scene import load_scene  # noqa: E402
from thesis_fill_drain import OUTPUT, leg, run_scene, static_sweep  # noqa: E402


def plot(out: dict):
    fig, axes = plt.subplots(1, 2, figsize=(12, 4))
    for name, style in (("valve-fill", "o-"), ("thesis-fill", "s--")):
        if name not in out:
            continue
        for ref, colour in (("sweep", "tab:red"), ("same_fold", "tab:blue")):
            rows = out[name][ref]
            f = [r["fill"] for r in rows]
            axes[0].semilogy(f, [max(r["eqn_6_1"], 1e-6) for r in rows], style, color=colour,
                             label=f"{name}, against the {ref.replace('_', ' ')}")
            axes[1].plot(f, [r["level_difference"] for r in rows], style, color=colour,
                         label=f"{name}, {ref.replace('_', ' ')}")
    axes[0].set_ylabel("Eqn 6.1 dynamic against static (%)")
    axes[1].set_ylabel("pressure level, dynamic - static (Pa)")
    for ax in axes:
        ax.set_xlabel("tank fraction V / (4/3 pi R^3)")
        ax.grid(alpha=0.3, which="both")
    axes[0].legend(fontsize=7)
    fig.suptitle("valve-fill (1e-3 m^3/s, inertia) and thesis-fill (2e-5 m^3/s) against the "
                 "static model, N = 14, 16^3")
    return fig


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fill", type=Path)
    parser.add_argument("--thesis-fill", type=Path)
    args = parser.parse_args(argv)
    logging.getLogger().setLevel(logging.ERROR)
    OUTPUT.mkdir(exist_ok=True)
    fill = read_result(args.fill or run_scene("valve-fill", OUTPUT / "valve-fill",
                                              exit_codes=(0, 3)))
    t0 = time.perf_counter()
    static = static_sweep(load_scene("valve-fill"))
    out = {"valve-fill": leg(fill, static.groups["frames"]),
           "static_sweep_seconds": time.perf_counter() - t0}
    if args.thesis_fill is not None:
        out["thesis-fill"] = leg(read_result(args.thesis_fill), static.groups["frames"])
    (OUTPUT / "valve_fill.json").write_text(json.dumps(out, indent=1))
    fig = plot(out)
    fig.savefig(OUTPUT / "valve_fill.png", dpi=110, bbox_inches="tight")
    plt.close(fig)
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
