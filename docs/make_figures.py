"""The README's figure, from the results of three bundled scenes.

    fsi run thesis-static --out results/thesis-static
    fsi run slosh-half --out results/slosh-half
    fsi run slosh-diaphragm --out results/slosh-diaphragm
    python docs/make_figures.py [RESULTS]        # RESULTS: the folder holding those three

Writes ``docs/_static/figures/front.png``: the diaphragm's cross-section with the liquid below
it at five tank fractions V / (4/3 pi R^3) of the static fill (up to the full inversion), and
the free decay of the first lateral slosh mode at half fill (the liquid's centre of mass, from
where it started), free surface against diaphragm.
"""
from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from fsi.io.output import read_result  # noqa: E402
from fsi.io.plots import draw_tank, middle_column  # noqa: E402

FIGURE = Path(__file__).resolve().parent / "_static" / "figures" / "front.png"
N_SECTIONS = 5
FIRST_SECTION = 0.1
"""Cross-sections drawn: the frames nearest tank fractions evenly spread from FIRST_SECTION to
the sweep's largest."""
SLOSH = {"slosh-half": "free surface (limp diaphragm)", "slosh-diaphragm": "Table 4.1 diaphragm"}


def _section(ax, pos: np.ndarray, n: int, radius: float, title: str) -> None:
    """The tank wall, the membrane's middle grid line (y-z plane) and the liquid below it."""
    col = middle_column(pos, n)
    y, z = col[:, 1], col[:, 2]
    if y[0] > y[-1]:
        y, z = y[::-1], z[::-1]
    arc = np.linspace(0.0, -np.pi, 181)           # from (R, 0) under the bottom to (-R, 0)
    ax.fill(np.r_[y, radius * np.cos(arc)], np.r_[z, radius * np.sin(arc)], color="#9ecae1")
    draw_tank(ax, radius)
    ax.plot(y, z, "k-", lw=1.4)
    ax.set(aspect="equal", xticks=[], yticks=[], title=title)
    ax.title.set_fontsize(9)
    for side in ax.spines.values():
        side.set_visible(False)


def main(root: Path) -> Path:
    static = read_result(root / "thesis-static")
    radius, n = float(static["attrs"]["radius"]), int(static["attrs"]["grid_size"])
    frames = static["frames"]
    fig = plt.figure(figsize=(11, 6.2), constrained_layout=True)
    grid = fig.add_gridspec(2, N_SECTIONS, height_ratios=(1, 1.15))
    tank = np.asarray(frames["tank_fraction"])
    for k, target in enumerate(np.linspace(FIRST_SECTION, tank.max(), N_SECTIONS)):
        i = int(np.argmin(np.abs(tank - target)))
        _section(fig.add_subplot(grid[0, k]), frames["node_position"][i], n, radius,
                 f"tank fraction {frames['tank_fraction'][i]:.2f}")
    ax = fig.add_subplot(grid[1, :])
    for name, label in SLOSH.items():
        res = read_result(root / name)
        w, a = res["windows"], res["attrs"]
        x = w["centre_of_mass"][:, 0]
        ax.plot(w["time"], 1e3 * (x - x[0]),
                label=f"{label}: {a['frequency_hz']:.2f} Hz, $\\lambda_1$ = {a['lambda1']:.3f}")
    ax.set(xlabel="time (s)", ylabel="contents' centre of mass, x - x(0) (mm)",
           title="first lateral slosh mode at tank fraction 0.5: free decay after a 0.1 s pulse")
    ax.grid(alpha=0.3)
    ax.legend()
    FIGURE.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(FIGURE, dpi=80)
    plt.close(fig)
    return FIGURE


if __name__ == "__main__":
    print(main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results")))
