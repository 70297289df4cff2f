"""The plots of a shell-of-revolution run (:mod:`fsi.procedures.shell_of_revolution`):

* ``cross_sections.png``: the meridian at each fill (the section through the axis, both
  halves), coloured by tank fraction on a colourbar, inside the tank; the liquid below the
  sheet shaded at the last fill;
* ``level_by_fill.png``: the liquid's pressure level along the fill and the drain, the snaps
  between branches dotted and the onset of folding marked;
* ``stability_map.png``: the fill's lowest eigenvalue omega^2 of each circumferential wave
  number n against the tank fraction (signed, symmetric log scale: red unstable), the onset
  starred;
* ``slosh_by_fill.png``: lambda1 of the n = 1 slosh mode against the tank fraction (log
  scale; hollow where the branch is unstable to some harmonic) beside the free surface's,
  and the slosh mass of each (when the run found the slosh modes).
"""
from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib import colors

from fsi.io.plot_registry import register_plots, save
from fsi.io.stress_plots import TANK_FRACTION


def _events(res: dict) -> list[tuple[str, float, float, int]]:
    events = res.get("axisymmetric_events", {})
    out = []
    for k, event in enumerate(events.get("event", [])):
        text = event.decode() if isinstance(event, bytes) else str(event)
        out.append((text, float(events["tank_fraction"][k]),
                    float(events["pressure_level"][k]), int(events["lobes"][k])))
    return out


def _cross_sections(res: dict, path: Path) -> Path:
    fill, radius = res["axisymmetric_fill"], float(res["attrs"]["radius"])
    f = np.asarray(fill["tank_fraction"])
    norm = colors.Normalize(0.0, 1.0)
    cmap = plt.get_cmap("viridis")
    fig, ax = plt.subplots(figsize=(6.4, 6.0))
    theta = np.linspace(0, 2 * np.pi, 361)
    ax.plot(radius * np.cos(theta), radius * np.sin(theta), color="0.3", lw=1.5, label="tank")
    r_last, z_last = fill["meridian_radius"][-1], fill["meridian_height"][-1]
    lower = np.linspace(-np.pi / 2, 0, 91)
    ax.fill(np.concatenate([r_last, radius * np.cos(lower[::-1])]),
            np.concatenate([z_last, radius * np.sin(lower[::-1])]), color="tab:blue",
            alpha=0.12, lw=0, label=f"liquid at {f[-1]:.3f}")
    ax.fill(-np.concatenate([r_last, radius * np.cos(lower[::-1])]),
            np.concatenate([z_last, radius * np.sin(lower[::-1])]), color="tab:blue",
            alpha=0.12, lw=0)
    for k in range(len(f)):
        r, z = fill["meridian_radius"][k], fill["meridian_height"][k]
        ax.plot(np.concatenate([-r[::-1], r]), np.concatenate([z[::-1], z]),
                color=cmap(norm(f[k])), lw=1.0)
    fig.colorbar(plt.cm.ScalarMappable(norm, cmap), ax=ax, label=TANK_FRACTION, shrink=0.8)
    ax.set(aspect="equal", xlabel="x (m)", ylabel="z (m)",
           title="The diaphragm's section at each fill")
    ax.legend(fontsize=8, loc="upper right")
    return save(fig, path)


def _level_by_fill(res: dict, path: Path) -> Path:
    fill, drain = res["axisymmetric_fill"], res.get("axisymmetric_drain")
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    ax.plot(fill["tank_fraction"], fill["pressure_level"], "o-", ms=3, label="fill")
    if drain is not None:
        ax.plot(drain["tank_fraction"], drain["pressure_level"], "s--", ms=4, mfc="none",
                label="drain")
    snapped = False
    for text, at, level, lobes in _events(res):
        if "snaps" in text:
            ax.axvline(at, color="k", ls=":", lw=1, label=None if snapped else "snaps")
            snapped = True
        elif text.startswith("fill"):
            ax.axvline(at, color="tab:red", lw=1,
                       label=f"folding starts, {lobes} lobes ({at:.4f})")
    ax.set(xlabel=TANK_FRACTION, ylabel="pressure level p_ref (Pa)",
           title="Level along the fill and the drain (axisymmetric branch)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return save(fig, path)


def _stability_map(res: dict, path: Path) -> Path:
    fill = res["axisymmetric_fill"]
    f = np.asarray(fill["tank_fraction"])
    waves = np.asarray(res["attrs"]["wave_number"])
    values = np.asarray(fill["harmonic_eigenvalue"]).T
    scale = float(np.nanmax(np.abs(values)))
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    mesh = ax.pcolormesh(f, waves, values, shading="nearest", cmap="RdBu",
                         norm=colors.SymLogNorm(linthresh=1e-3 * scale, vmin=-scale,
                                                vmax=scale))
    fig.colorbar(mesh, ax=ax, label="lowest ω² of harmonic n (1/s²); red: unstable")
    for text, at, _, lobes in _events(res):
        if text.startswith("fill") and lobes:
            ax.plot(at, lobes, "k*", ms=12, label=f"folding starts: n = {lobes} at {at:.4f}")
    ax.set(xlabel=TANK_FRACTION, ylabel="circumferential wave number n",
           title="Stability of the fill's axisymmetric branch by wave number")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8, loc="upper right")
    return save(fig, path)


def _slosh_by_fill(res: dict, path: Path) -> Path:
    slosh = res["axisymmetric_slosh"]
    f = np.asarray(slosh["tank_fraction"])
    lam, free = np.asarray(slosh["lambda1"]), np.asarray(slosh["lambda1_free"])
    stable = np.asarray(slosh["stable"], dtype=bool)
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.2))
    a.plot(f, free, "s--", color="0.4", mfc="none", label="free surface")
    a.plot(f, lam, "-", color="tab:blue", lw=1)
    a.plot(f[stable], lam[stable], "o", color="tab:blue", label="diaphragm (branch stable)")
    a.plot(f[~stable], lam[~stable], "o", color="tab:blue", mfc="none",
           label="diaphragm (branch unstable to some n)")
    a.set(yscale="log", xlabel=TANK_FRACTION, ylabel="λ1 = ω² a / g",
          title="n = 1 slosh mode on the fill's axisymmetric branch")
    a.grid(alpha=0.3, which="both")
    a.legend(fontsize=8)
    b.plot(f, slosh["free_slosh_mass_fraction"], "s--", color="0.4", mfc="none",
           label="free surface")
    b.plot(f, slosh["slosh_mass_fraction"], "o-", color="tab:blue", ms=4, label="diaphragm")
    b.set(xlabel=TANK_FRACTION, ylabel="slosh mass / liquid mass", ylim=(0, 1),
          title="Slosh mass of that mode")
    b.grid(alpha=0.3)
    b.legend(fontsize=8)
    fig.tight_layout()
    return save(fig, path)


@register_plots("shell-of-revolution")
def axisymmetric_plots(res: dict, out: Path) -> list[Path]:
    """The plots of the module doc."""
    paths = [_cross_sections(res, out / "cross_sections.png"),
             _level_by_fill(res, out / "level_by_fill.png"),
             _stability_map(res, out / "stability_map.png")]
    if len(res.get("axisymmetric_slosh", {}).get("tank_fraction", [])):
        paths.append(_slosh_by_fill(res, out / "slosh_by_fill.png"))
    return paths
