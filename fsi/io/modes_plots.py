"""The plots of a ``modes`` run (:mod:`fsi.procedures.modes`), from ``result.h5``:

* ``modes_by_fill.png``: the first lateral mode's lambda1 = omega^2 R / g, its slosh mass
  fraction and the heights of its slosh mass and hinge (over R) against the tank fraction;
* ``mode_shapes.png`` (free and tensioned surfaces): the surface's elevation in the first
  modes at the fill nearest half, over the grid's columns (plan view), each titled with its
  azimuthal order and frequency.
"""
from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from fsi.io.plot_registry import register_plots, save as _save

SHAPES_SHOWN = 6
"""Modes drawn in ``mode_shapes.png``."""


@register_plots("modes")
def modes_plots(res: dict, out: Path) -> list[Path]:
    written = [_by_fill(res, out / "modes_by_fill.png")]
    if "shapes" in res:  # a surface's elevation (the diaphragm's modes have none)
        written.append(_shapes(res, out / "mode_shapes.png"))
    return written


def _by_fill(res: dict, path: Path) -> Path:
    f, a = res["fills"], res["attrs"]
    radius = float(a["radius"])
    fill = f["tank_fraction"]
    fig, axes = plt.subplots(3, 1, figsize=(6, 8), sharex=True)
    axes[0].plot(fill, f["lambda1"], "o-")
    axes[0].set_ylabel("lambda1 = omega$^2$ R / g")
    axes[1].plot(fill, f["slosh_mass_fraction"], "o-")
    axes[1].set_ylabel("slosh mass / liquid mass")
    axes[2].plot(fill, f["slosh_mass_height"] / radius, "o-", label="slosh mass")
    axes[2].plot(fill, f["hinge_height"] / radius, "s--", label="pendulum hinge")
    axes[2].plot(fill, f["level"] / radius, ":", color="0.5", label="level")
    axes[2].set_ylabel("height / R (tank centre 0)")
    axes[2].set_xlabel("tank fraction V / (4/3 pi R$^3$)")
    axes[2].legend(fontsize=8)
    for ax in axes:
        ax.grid(alpha=0.3)
    axes[0].set_title(f"first lateral slosh mode, {a['surface']} surface, "
                      f"{a['fluid_cells']}$^3$ cells")
    return _save(fig, path)


def _shapes(res: dict, path: Path) -> Path:
    f, m, s = res["fills"], res["modes"], res["shapes"]
    k = int(np.argmin(np.abs(f["tank_fraction"] - 0.5)))
    fill = float(f["tank_fraction"][k])
    mine = np.flatnonzero(np.isclose(m["tank_fraction"], fill))
    elevation = s["elevation"][k]
    shown = min(SHAPES_SHOWN, len(mine), elevation.shape[-1])
    cols = 3
    rows = int(np.ceil(shown / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 3.2 * rows), squeeze=False)
    for j, ax in enumerate(axes.flat):
        ax.set_axis_off()
        if j >= shown:
            continue
        field = elevation[..., j].T
        scale = np.nanmax(np.abs(field))
        ax.imshow(field, origin="lower", cmap="RdBu_r", vmin=-scale, vmax=scale)
        row = mine[j]
        ax.set_title(f"mode {j + 1}: m = {int(m['azimuthal_order'][row])}, "
                     f"{m['frequency_hz'][row]:.3f} Hz", fontsize=9)
    fig.suptitle(f"surface elevation, tank fraction {fill:.3f} (plan view, x right)")
    return _save(fig, path)
