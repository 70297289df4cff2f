"""PNG plots made from ``result.h5`` (never inside a time loop).

* ``cross_section_fill_XXX.png`` (``_tank_XXX`` on the tank-fraction scale; XXX the target
  in %): the membrane's middle grid line in the y-z plane with the tank wall, as thesis
  Figs 6.2-6.8 (App. J plots the grid column round(N/2));
* ``surface_fill_XXX.png``: the 3-D render of the membrane in the tank with the liquid
  (:mod:`fsi.io.render`), coloured by von Mises stress on one scale for the run; titles give
  the tank fraction V / (4/3 pi R^3); not made (one line says why) where the renderer is
  missing;
* ``cross_sections.png``: all fills of a group in one panel (filling and draining side by
  side), each curve coloured by its tank fraction;
* ``coupling.png`` (coupled-fill runs): coupling iterations, pressure level and liquid volume
  per window against time;
* ``slosh.png`` (slosh runs): the tank's acceleration, the liquid's centre of mass, the force
  and moment on the tank and the energies against time;
* ``plate_profiles.png``, ``plate_profiles_nondimensional.png``, ``plate_radius_trend.png``
  (plate-estimate runs): thesis Figs 3.2-3.4, every closed form, dashed outside its range;
* ``stress_envelope.png`` and ``diaphragm_history.png`` (every run with membrane frames):
  :mod:`fsi.io.stress_plots`.

Each procedure whose results are not membrane frames registers its plots in :data:`PLOTS`.
"""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from fsi.io import axisymmetric_plots as _axisymmetric_plots  # noqa: E402,F401  (registers)
from fsi.io import modes_plots as _modes_plots  # noqa: E402,F401  (registers its plots)
from fsi.io import render  # noqa: E402
from fsi.io.output import read_result  # noqa: E402
from fsi.io.plot_registry import PLOTS, register_plots, save as _save  # noqa: E402
from fsi.io.stress_plots import TANK_FRACTION, stress_plots  # noqa: E402


def middle_column(pos: np.ndarray, n: int) -> np.ndarray:
    """(N, 3) nodes of grid column round(N/2) (1-based), App. J's cross-section line."""
    return pos.reshape(n, n, 3)[:, n // 2 - 1, :]


def draw_tank(ax, radius):
    """The tank wall (a circle of ``radius``, m) and the equator on a y-z plot."""
    t = np.linspace(0, 2 * np.pi, 361)
    ax.plot(radius * np.cos(t), radius * np.sin(t), color="0.6", lw=1)
    ax.axhline(0.0, color="0.85", lw=0.8)


def make_plots(run_dir) -> list[Path]:
    """Write the PNGs of the run in ``run_dir`` into ``run_dir/plots``; returns their paths."""
    run_dir = Path(run_dir)
    res = read_result(run_dir)
    out = run_dir / "plots"
    out.mkdir(exist_ok=True)
    return PLOTS.get(res["attrs"].get("procedure"), membrane_plots)(res, out) \
        + stress_plots(res, out)


def membrane_plots(res: dict, out: Path) -> list[Path]:
    """Cross-section and 3-D surface of every frame, all cross-sections, and the coupling
    history of a coupled run."""
    radius, n = float(res["attrs"]["radius"]), int(res["attrs"]["grid_size"])
    scale = str(res["attrs"].get("fill_scale", "full-inversion"))
    frames = res["frames"]
    named = [(k, fill_label(frames, k), frame_tag(frames, k, scale))
             for k in range(len(frames["node_position"]))]
    written = [_cross_section_plot(frames["node_position"][k], n, radius, label,
                                   out / f"cross_section_{tag}.png") for k, label, tag in named]
    written += _surface_plots(res, [(k, label, out / f"surface_{tag}.png")
                                    for k, label, tag in named])
    written.append(_cross_sections_plot(res, n, radius, out / "cross_sections.png"))
    if "windows" in res:
        written.append(_coupling_plot(res, out))
    return written


FILE_TAGS = {"full-inversion": "fill", "tank": "tank"}
"""Fill scale -> the word before the target fill (%) in the names of a frame's plots."""


def frame_tag(group: dict, k: int, scale: str) -> str:
    """The name of frame ``k``'s plots: the scale's word and the target fill (%), or the
    frame's number where it has no target."""
    target = group["target_fill"][k] if "target_fill" in group else np.nan
    return f"{FILE_TAGS.get(scale, 'fill')}_{100 * float(target):05.1f}" \
        if np.isfinite(target) else f"fill_{k:03d}"


def fill_label(group: dict, k: int) -> str:
    """How a frame's fill is titled: its tank fraction V / (4/3 pi R^3) on every fill scale;
    a frame whose solve (or window) did not converge says so."""
    text = f"tank fraction {float(group['tank_fraction'][k]):.3f}"
    if "converged" in group and not bool(group["converged"][k]):
        text += " - NOT CONVERGED"
    return text


def _cross_section_plot(pos, n: int, radius: float, label: str, path: Path) -> Path:
    """The middle grid line in the y-z plane with the tank wall (thesis Figs 6.2-6.8)."""
    col = middle_column(pos, n)
    fig, ax = plt.subplots(figsize=(6, 5))
    draw_tank(ax, radius)
    ax.plot(col[:, 1], col[:, 2], "k-o", ms=2, lw=1.5, label="membrane")
    ax.set_aspect("equal")
    ax.set_xlabel("y (m)")
    ax.set_ylabel("z (m)")
    ax.set_title(f"Cross section, {label}", fontsize=10)
    return _save(fig, path)


def _surface_plots(res: dict, wanted: list[tuple[int, str, Path]]) -> list[Path]:
    """The 3-D renders of frames ``wanted`` [(frame, title, path)] of the main group, in
    the tank with the liquid, coloured by von Mises stress (the displacement without the
    stress analysis) on one scale for the run (0 to the 99th percentile of the free sheet
    over all its frames); none where the renderer is missing."""
    if not wanted or not render.usable():
        return []
    field = render.first_available(res["frames"])
    frames = [render.frame_of(res, "frames", k) for k, _, _ in wanted]
    clim = render.percentile_scale(np.concatenate([render.sheet_values(f, field)
                                                   for f in frames]))
    note = (f"colour scale to the 99th percentile of the run's free sheet, "
            f"{clim[1]:.3g} {render.FIELDS[field].unit}")
    with render.Renderer() as renderer:
        return [renderer.save(render.View(frame, field, clim, title=f"Membrane, {label}",
                                          note=note), path)
                for frame, (_, label, path) in zip(frames, wanted)]


def _cross_sections_plot(res: dict, n: int, radius: float, path: Path) -> Path:
    """All cross-sections of the filling and draining groups, side by side, each coloured
    by its tank fraction (one colourbar)."""
    groups = [g for g in ("frames", "drain") if g in res]
    fig, axes = plt.subplots(1, len(groups), figsize=(5.2 * len(groups) + 1.2, 5),
                             squeeze=False, constrained_layout=True)
    top = max(float(np.max(res[g]["tank_fraction"])) for g in groups)
    colours = plt.cm.ScalarMappable(plt.Normalize(0.0, top), "viridis")
    for ax, name in zip(axes[0], groups):
        draw_tank(ax, radius)
        for k, pos in enumerate(res[name]["node_position"]):
            col = middle_column(pos, n)
            ax.plot(col[:, 1], col[:, 2], color=colours.to_rgba(res[name]["tank_fraction"][k]),
                    lw=1.2)
        ax.set_aspect("equal")
        ax.set_title({"frames": "filling", "drain": "draining"}[name]
                     + f", {len(res[name]['node_position'])} frames", fontsize=10)
        ax.set_xlabel("y (m)")
        ax.set_ylabel("z (m)")
    fig.colorbar(colours, ax=axes[0].tolist(), shrink=0.85, label=TANK_FRACTION)
    return _save(fig, path)


def _coupling_plot(res: dict, out: Path) -> Path:
    """Iterations, level and volumes per window of a coupled-fill run."""
    w = res["windows"]
    t = w["time"]
    fig, axes = plt.subplots(3, 1, figsize=(7, 8), sharex=True)
    axes[0].plot(t, w["coupling_iterations"], ".-")
    axes[0].set_ylabel("coupling iterations")
    axes[1].plot(t, w["pressure_level"], ".-")
    axes[1].set_ylabel("pressure level (Pa)")
    v0 = float(res["attrs"]["start_volume"])
    f0 = float(res["frames"]["fluid_liquid_volume"][0])
    axes[2].plot(t, w["delivered_volume"], "k-", label="delivered by the port")
    axes[2].plot(t, w["liquid_volume"] - v0, ".", label="membrane")
    axes[2].plot(t, w["fluid_liquid_volume"] - f0, "x", label="fluid cut cells")
    axes[2].set_ylabel("liquid volume change (m$^3$)")
    axes[2].set_xlabel("time (s)")
    axes[2].legend(fontsize=8)
    for ax in axes:
        ax.grid(alpha=0.3)
    return _save(fig, out / "coupling.png")


@register_plots("slosh")
def slosh_plots(res: dict, out: Path) -> list[Path]:
    return [_slosh_plot(res, out / "slosh.png")]


def _slosh_plot(res: dict, path: Path) -> Path:
    """Acceleration, centre of mass, force, moment and energies of a slosh run."""
    w, a = res["windows"], res["attrs"]
    t = w["time"]
    fig, axes = plt.subplots(5, 1, figsize=(7, 11), sharex=True)
    axes[0].plot(t, w["tank_acceleration"][:, 0])
    axes[0].set_ylabel("tank a$_x$ (m/s$^2$)")
    axes[1].plot(t, 1e3 * w["centre_of_mass"][:, 0])
    axes[1].set_ylabel("contents x$_c$ (mm)")
    axes[2].plot(t, w["force"][:, 0])
    axes[2].set_ylabel("F$_x$ on tank (N)")
    axes[3].plot(t, w["moment"][:, 1])
    axes[3].set_ylabel("M$_y$ on tank (N m)")
    parts = {"liquid kinetic": w["liquid_kinetic_energy"],
             "gravitational potential": w["potential_energy"],
             "dissipated (liquid)": w["dissipated_energy"]}
    if "membrane_kinetic_energy" in w:
        parts["membrane kinetic"] = w["membrane_kinetic_energy"]
        parts["membrane elastic (change)"] = w["membrane_elastic_energy"] - \
            w["membrane_elastic_energy"][0]
    total = sum(parts.values())
    for label, value in parts.items():
        axes[4].plot(t, 1e3 * value, label=label)
    axes[4].plot(t, 1e3 * total, "k", label="sum")
    axes[4].set_ylabel("energy (mJ)")
    axes[4].set_xlabel("time (s)")
    axes[4].legend(fontsize=7)
    for ax in axes:
        ax.grid(alpha=0.3)
    title = f"{a['surface']} surface, tank fraction {a['tank_fraction']:.3f} (V / (4/3 pi R$^3$))"
    if "lambda1" in a:
        title += f"\n{a['frequency_hz']:.3f} Hz, lambda1 {a['lambda1']:.4f}, zeta {a['zeta']:.4f}"
    axes[0].set_title(title)
    return _save(fig, path)


def _estimate_style(name: str) -> dict:
    return {"small": dict(color="tab:blue"), "large": dict(color="tab:orange"),
            "hencky": dict(color="tab:green")}.get(name, {})


def _estimate_names(group: dict) -> list[str]:
    return [k.removeprefix("valid_") for k in group if k.startswith("valid_")]


@register_plots("plate-estimate")
def plate_plots(res: dict, out: Path) -> list[Path]:
    """Thesis Figs 3.2 (profiles), 3.3 (the same over t and a) and 3.4 (w0 / a against the
    tank radius), every estimate, solid inside its validity range and dashed outside."""
    g, a = res["plate"], res["attrs"]
    t, radius = float(a["thickness"]), float(a["flat_radius"])
    names = _estimate_names(g)
    written = []
    for scaled, path in ((False, "plate_profiles.png"),
                         (True, "plate_profiles_nondimensional.png")):
        fig, ax = plt.subplots(figsize=(7, 4.5))
        top = 0.0
        for k, fill in enumerate(g["tank_fraction"]):
            r = g["radial_position"][k]
            x, sx = (r / radius, 1.0 / t) if scaled else (r, 1e3)
            for name in names:
                w = g[f"deflection_{name}"][k] * sx
                style = "-" if g[f"valid_{name}"][k] else "--"
                ax.plot(np.r_[-x[::-1], x], -np.r_[w[::-1], w], style, lw=1.0 + 2 * fill,
                        label=f"{name}, tank fraction {fill:.2f}", **_estimate_style(name))
                if name != "small":
                    top = max(top, w.max())
        ax.set_ylim(-1.3 * top, 0.1 * top)  # the linear plate leaves the scale: see the legend
        ax.set_xlabel("r / a" if scaled else "r (m)")
        ax.set_ylabel("w / t" if scaled else "w (mm)")
        ax.set_title(f"Flat diaphragm a = {radius:.4f} m, t = {1e3 * t:.3f} mm, "
                     f"{a['load']} load\n(dashed: outside the estimate's validity range)")
        ax.legend(fontsize=7, ncol=2)
        ax.grid(alpha=0.3)
        written.append(_save(fig, out / path))
    written.append(_plate_trend_plot(res, names, out / "plate_radius_trend.png"))
    return written


def _plate_trend_plot(res: dict, names: list[str], path: Path) -> Path:
    s, g = res["radius_sweep"], res["plate"]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    r = s["tank_radius"]
    for j, fill in enumerate(g["tank_fraction"]):
        for name in names:
            ratio = s[f"centre_deflection_{name}"][:, j] / r
            valid = s[f"valid_{name}"][:, j].astype(bool)
            ax.plot(r, np.where(valid, ratio, np.nan), "-", lw=1 + 2 * fill,
                    label=f"{name}, tank fraction {fill:.2f}", **_estimate_style(name))
            ax.plot(r, np.where(valid, np.nan, ratio), "--", lw=0.8, **_estimate_style(name))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("tank radius = diaphragm radius a (m)")
    ax.set_ylabel("centre deflection / radius, w0 / a")
    ax.axvline(float(res["attrs"]["flat_radius"]), color="0.6", lw=0.8)
    ax.set_title(f"t = {1e3 * float(res['attrs']['thickness']):.3f} mm "
                 "(dashed: outside the validity range)")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3, which="both")
    return _save(fig, path)
