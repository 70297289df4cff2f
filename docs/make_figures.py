"""The README's figure, from the results of three bundled scenes.

    fsi run thesis-static --out results/thesis-static
    fsi run slosh-half --out results/slosh-half
    fsi run slosh-diaphragm --out results/slosh-diaphragm
    python docs/make_figures.py [RESULTS]        # RESULTS: the folder holding those three

Writes ``docs/_static/figures/front.png``: top, 3-D renders (:mod:`fsi.io.render`) of the
static fill at four tank fractions V / (4/3 pi R^3) up to the full inversion, the diaphragm
coloured by von Mises stress on one scale (to the 99th percentile of the four free sheets),
the liquid below it and the tank; bottom, the free decay of the first lateral slosh mode at
half fill (the liquid's centre of mass, from where it started), free surface against
diaphragm.
"""
from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from fsi.io import render  # noqa: E402
from fsi.io.output import read_result  # noqa: E402

FIGURE = Path(__file__).resolve().parent / "_static" / "figures" / "front.png"
N_PANELS = 4
FIRST_PANEL = 0.15
"""Frames rendered: those nearest tank fractions evenly spread from FIRST_PANEL to the
sweep's largest."""
PANEL_WINDOW = (760, 640)
"""Render window of a panel (width, height), pixels; the panel is the render cropped to
what it shows."""
TOP_PERCENTILE = 99.0
FIELD = "von_mises"
SLOSH = {"slosh-half": lambda a: "free surface (limp diaphragm)",
         "slosh-diaphragm": lambda a: f"Table 4.1 diaphragm, N = {int(a['grid_size'])} grid "
                                      "(not converged in the grid)"}
"""Slosh result -> its curve's label from its attributes."""


def panel_frames(frames: dict) -> list[int]:
    """The frames of the panels (:data:`N_PANELS`, :data:`FIRST_PANEL`), in fill order."""
    tank = np.asarray(frames["tank_fraction"], dtype=float)
    targets = np.linspace(FIRST_PANEL, np.nanmax(tank), N_PANELS)
    return [int(np.nanargmin(np.abs(tank - t))) for t in targets]


def trimmed(image: np.ndarray, margin: int = 6) -> np.ndarray:
    """``image`` (h, w, 3) uint8 cropped to its non-white pixels and ``margin`` pixels."""
    rows, cols = np.nonzero((image < 250).any(axis=2))
    if rows.size == 0:
        return image
    return image[max(rows.min() - margin, 0):rows.max() + margin + 1,
                 max(cols.min() - margin, 0):cols.max() + margin + 1]


def _render_panels(static: dict, picks: list[int], clim) -> list[np.ndarray]:
    """The renders of frames ``picks`` of the static fill, no colourbar, no text."""
    with render.Renderer(PANEL_WINDOW) as renderer:
        return [trimmed(renderer.image(render.View(render.frame_of(static, "frames", k),
                                                   FIELD, clim, colourbar=False,
                                                   camera=render.Camera(distance=4.0))))
                for k in picks]


def _colour_scale(static: dict, picks: list[int]) -> tuple[float, float]:
    values = [render.sheet_values(render.frame_of(static, "frames", k), FIELD) for k in picks]
    return render.percentile_scale(np.concatenate(values), TOP_PERCENTILE)


def _colourbar(fig, ax, clim) -> None:
    """The panels' shared colourbar on ``ax``: the renders' colour map, values above the
    scale in their colour."""
    cmap = plt.get_cmap(render.CMAP).with_extremes(over=render.ABOVE_COLOUR)
    mappable = plt.cm.ScalarMappable(plt.Normalize(*clim), cmap)
    bar = fig.colorbar(mappable, cax=ax, extend="max")
    bar.set_label(f"{render.FIELDS[FIELD].label},\nscale to the {TOP_PERCENTILE:.0f}th "
                  "percentile", fontsize=9)


def _slosh_panel(ax, root: Path) -> None:
    for name, label in SLOSH.items():
        res = read_result(root / name)
        w, a = res["windows"], res["attrs"]
        x = w["centre_of_mass"][:, 0]
        ax.plot(w["time"], 1e3 * (x - x[0]),
                label=f"{label(a)}: {a['frequency_hz']:.2f} Hz, "
                      f"$\\lambda_1$ = {a['lambda1']:.3f}")
    ax.set(xlabel="time (s)", ylabel="contents' centre of mass, x - x(0) (mm)",
           title="first lateral slosh mode at tank fraction V / (4/3 $\\pi$ R$^3$) = 0.5: "
                 "free decay after a 0.1 s pulse")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=9, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2,
              frameon=False)


def main(root: Path) -> Path:
    static = read_result(root / "thesis-static")
    frames = static["frames"]
    picks = panel_frames(frames)
    clim = _colour_scale(static, picks)
    images = _render_panels(static, picks, clim)
    fig = plt.figure(figsize=(12, 7.6), constrained_layout=True)
    grid = fig.add_gridspec(2, N_PANELS + 1, height_ratios=(1.15, 1),
                            width_ratios=[1] * N_PANELS + [0.06])
    for j, (k, image) in enumerate(zip(picks, images)):
        ax = fig.add_subplot(grid[0, j])
        ax.imshow(image)
        ax.set_axis_off()
        ax.set_title(f"tank fraction {frames['tank_fraction'][k]:.2f}", fontsize=11)
    _colourbar(fig, fig.add_subplot(grid[0, N_PANELS]), clim)
    _slosh_panel(fig.add_subplot(grid[1, :]), root)
    fig.suptitle("The static fill of thesis-static: the diaphragm, coloured by von Mises "
                 "stress, above the liquid (blue) in the tank, by tank fraction "
                 "V / (4/3 $\\pi$ R$^3$)", fontsize=11)
    FIGURE.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(FIGURE, dpi=100)
    plt.close(fig)
    return FIGURE


if __name__ == "__main__":
    print(main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results")))
