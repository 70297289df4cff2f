"""A tensioned membrane on the liquid of an upright cylinder, membrane and liquid coupled in
the time domain through the coupling library, against Bauer's hydroelastic series.

    python benchmarks/tensioned_membrane.py [--gammas 0.01 0.1 1] [--depths 0.5 1]
                                            [--cells 24 32] [--smoke]

Runs :func:`cases.tensioned_membrane.couple` (a pinned sheet of uniform tension T and 1.2
kg/m^2 on an upright cylinder of radius a = 0.15 m and depth h, coupled implicit-serial with
IQN-ILS, a lateral pulse then free decay) at each Gamma = T / (rho g a^2), depth ratio h / a
and grid, and prints one JSON object: ``cases``, one per run, {``gamma``, ``depth_ratio``,
``cells``, ``lambda1`` = omega^2 a / g, ``series`` (the Rayleigh-Ritz series with the
sheet's mass, :mod:`fsi.analysis.membrane_series`), ``error`` (relative), ``zeta``,
``mean_iterations``, ``max_iterations``, ``unconverged`` windows, ``wall_seconds``}, and
``extrapolated``, per Gamma and depth with two grids or more, Richardson's value at order 2
from the two finest and its error. Writes ``benchmarks/output/tensioned_membrane.png``
(error against cell size); a full run's JSON also goes to
``docs/data/tensioned_membrane.json``. ``--smoke``: Gamma 0.1, h = a on 10^3 and 12^3 cells,
two periods at 30 windows.
"""
from __future__ import annotations

import argparse
import logging

from _report import SMOKE_HELP, emit, output_dir
from cases.tensioned_membrane import couple

DOC_FIELDS = ("cases", "extrapolated", "periods", "windows_per_period")
FIGURE_NAME = "tensioned_membrane.png"
PERIODS = 3.0
WINDOWS_PER_PERIOD = 50
SMOKE = dict(gammas=[0.1], depths=[1.0], cells=[10, 12], periods=2.0, windows=30)


def spacing_ratio(coarse: int, fine: int) -> float:
    """h_coarse / h_fine on the case's grids (h = 2a / (cells - 3))."""
    return (fine - 3) / (coarse - 3)


def extrapolated(cases: list[dict]) -> list[dict]:
    out = []
    for key in sorted({(c["gamma"], c["depth_ratio"]) for c in cases}):
        runs = sorted((c for c in cases if (c["gamma"], c["depth_ratio"]) == key),
                      key=lambda c: c["cells"])
        if len(runs) < 2:
            continue
        coarse, fine = runs[-2], runs[-1]
        ratio = spacing_ratio(coarse["cells"], fine["cells"]) ** 2
        value = fine["lambda1"] + (fine["lambda1"] - coarse["lambda1"]) / (ratio - 1)
        out.append(dict(gamma=key[0], depth_ratio=key[1],
                        cells=[coarse["cells"], fine["cells"]], lambda1=value,
                        series=fine["series"], error=value / fine["series"] - 1))
    return out


def plot(cases: list[dict], figure) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    for key in sorted({(c["gamma"], c["depth_ratio"]) for c in cases}):
        runs = sorted((c for c in cases if (c["gamma"], c["depth_ratio"]) == key),
                      key=lambda c: c["cells"])
        h = [2.0 / (c["cells"] - 3) for c in runs]
        ax.loglog(h, [abs(c["error"]) for c in runs], "o-",
                  label=f"$\\Gamma$ = {key[0]:g}, h/a = {key[1]:g}")
    ax.axhline(0.02, color="k", lw=0.5, ls="--")
    ax.set_xlabel("cell size / a")
    ax.set_ylabel("|$\\lambda_1$ / series - 1|")
    ax.set_title("tensioned membrane coupled with its liquid")
    ax.legend(fontsize=7)
    figure.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(figure, dpi=110, bbox_inches="tight")
    plt.close(fig)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--gammas", type=float, nargs="+", default=[0.01, 0.1, 1.0])
    parser.add_argument("--depths", type=float, nargs="+", default=[0.5, 1.0])
    parser.add_argument("--cells", type=int, nargs="+", default=[24, 32])
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args()
    periods, windows = PERIODS, WINDOWS_PER_PERIOD
    if args.smoke:
        args.gammas, args.depths, args.cells = SMOKE["gammas"], SMOKE["depths"], SMOKE["cells"]
        periods, windows = SMOKE["periods"], SMOKE["windows"]
    logging.basicConfig(level=logging.WARNING)
    cases = []
    for gamma in args.gammas:
        for depth in args.depths:
            for cells in args.cells:
                o = couple(gamma, depth, cells, periods=periods, windows_per_period=windows)
                cases.append(dict(gamma=gamma, depth_ratio=depth, cells=cells,
                                  lambda1=o.lambda1, series=o.series, error=o.error,
                                  zeta=o.zeta, mean_iterations=o.mean_iterations,
                                  max_iterations=o.max_iterations, unconverged=o.unconverged,
                                  wall_seconds=o.seconds))
    figure = output_dir(args.smoke) / FIGURE_NAME
    plot(cases, figure)
    emit("tensioned_membrane", dict(cases=cases, extrapolated=extrapolated(cases),
                                    periods=periods, windows_per_period=windows,
                                    figure=str(figure)), args.smoke)


if __name__ == "__main__":
    main()
