"""The validation pages' figures and the performance page's speed-against-accuracy chart,
drawn from the measurements in ``docs/data/*.json``.

    python docs/make_validation_figures.py              # every figure
    python docs/make_validation_figures.py fluid slosh  # the named ones (FIGURES' keys)

Writes ``docs/_static/figures/validation_<name>.png`` for each figure and prints its path.
Every number drawn is read from the JSON a benchmark wrote (the files the pages' tables
read), so a figure cannot drift from its table: rerun this after a benchmark refreshes its
JSON. Each figure names the files it read and their commits along its bottom edge.
"""
from __future__ import annotations

import json
import math
import sys
import textwrap
from collections.abc import Callable
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib import ticker  # noqa: E402
from matplotlib.transforms import Bbox  # noqa: E402

DOCS = Path(__file__).resolve().parent
DATA = DOCS / "data"
FIGURES_DIR = DOCS / "_static" / "figures"
DPI = 90
plt.rcParams["figure.dpi"] = DPI  # laid out at the saved resolution: labels placed in pixels
WIDTH = 9.0
"""Figure width (inches): 810 pixels at DPI, about the page's text width."""
REFERENCE = dict(color="k", lw=1.3, zorder=1)
"""How a reference (a closed form, a published value, a bound) is drawn: a black line."""
GUIDE = dict(color="0.45", lw=1.0, ls=":", zorder=1)
"""How an order-of-convergence guide is drawn."""
LEGEND = dict(fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)
"""Legends stand to the right of their axes, clear of the data."""
FILL_COLOURS = {0.3: "tab:blue", 0.5: "tab:green", 0.7: "tab:purple"}

# The bounds tests/test_fluid.py asserts and docs/validation/fluid.md states as goals: not
# measurements, so not in the JSON.
POISEUILLE_GOAL = 0.01
PISTON_GOAL = 0.02
SLOSH_BAND = 0.01
"""The band drawn about a slosh reference: docs/validation/slosh.md's "within about 1 %"."""


# -- data, axes and output -------------------------------------------------------------------

def load(name: str) -> dict:
    """The JSON object of ``docs/data/NAME.json``."""
    return json.loads((DATA / f"{name}.json").read_text(encoding="utf-8"))


def _plain(value: float, _position=None) -> str:
    return f"{value:g}"


def _plain_minor(value: float, _position=None) -> str:
    """Label the minor log ticks at 2 and 5 of each decade only."""
    if value <= 0:
        return ""
    mantissa = round(value / 10 ** math.floor(math.log10(value) + 1e-9))
    return f"{value:g}" if mantissa in (2, 5) else ""


def log_axis(axis, minor_labels: bool = False) -> None:
    """A log axis labelled with plain numbers (0.1, 1, 10) instead of powers of ten."""
    axis.set_major_formatter(ticker.FuncFormatter(_plain))
    axis.set_minor_formatter(ticker.FuncFormatter(_plain_minor) if minor_labels
                             else ticker.NullFormatter())


def integer_ticks(axis, values) -> None:
    """Ticks at the grid sizes of a log axis, written as integers."""
    axis.set_major_locator(ticker.FixedLocator(sorted(values)))
    axis.set_major_formatter(ticker.FuncFormatter(_plain))
    axis.set_minor_locator(ticker.NullLocator())


def credit(fig: plt.Figure, *names: str) -> None:
    """The data files a figure read and their commits, along its bottom edge (space kept)."""
    text = "data (docs/data/, commit): " + ", ".join(
        f"{name}.json {load(name)['commit']}" for name in names)
    lines = textwrap.wrap(text, width=int(fig.get_figwidth() * 17))
    fig.text(0.995, 0.004, "\n".join(lines), ha="right", va="bottom", fontsize=7,
             color="0.4")
    bottom = (0.06 + 0.13 * len(lines)) / fig.get_figheight()
    fig.get_layout_engine().set(rect=(0, bottom, 1, 1 - bottom))  # left, bottom, w, h


def save(fig: plt.Figure, name: str) -> Path:
    path = FIGURES_DIR / f"validation_{name}.png"
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path


def order_guide(ax, x: np.ndarray, through: tuple[float, float], order: float,
                label: str) -> None:
    """A line of slope -order on log-log axes through the point ``through``."""
    x0, y0 = through
    ax.plot(x, y0 * (x0 / x) ** order, label=label, **GUIDE)


# -- labels that avoid each other --------------------------------------------------------------

_PLACES = [(5, 0, "left", "center"), (-5, 0, "right", "center"), (0, 5, "center", "bottom"),
           (0, -5, "center", "top"), (4, 4, "left", "bottom"), (4, -4, "left", "top"),
           (-4, 4, "right", "bottom"), (-4, -4, "right", "top")]
"""Where a label may stand from its point (offset in points, alignment), in order of choice;
then the same three times farther out, with a leader line."""


def label_points(fig: plt.Figure, ax, points: list[tuple[float, float, str, str]]) -> None:
    """Label each (x, y, text, colour) where its text overlaps no point, no other label and
    stays inside the axes. Lays the figure out first and freezes it, so labels stay put."""
    fig.canvas.draw()
    fig.set_layout_engine("none")
    renderer = fig.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    taken = [_point_box(ax, x, y) for x, y, _, _ in points]
    for x, y, text, colour in points:
        taken.append(_place(ax, renderer, frame, taken, x, y, text, colour))


def _point_box(ax, x: float, y: float, radius: float = 4.0) -> Bbox:
    px, py = ax.transData.transform((x, y))
    return Bbox.from_extents(px - radius, py - radius, px + radius, py + radius)


def _place(ax, renderer, frame, taken, x, y, text, colour):
    candidates = _PLACES + [(3 * dx, 3 * dy, ha, va) for dx, dy, ha, va in _PLACES]
    first = None
    for dx, dy, ha, va in candidates:
        far = abs(dx) + abs(dy) > 10
        note = ax.annotate(text, (x, y), xytext=(dx, dy), textcoords="offset points",
                           ha=ha, va=va, fontsize=8, color=colour,
                           arrowprops=dict(arrowstyle="-", color=colour, lw=0.5)
                           if far else None)
        box = note.get_window_extent(renderer)
        inside = frame.contains(box.x0, box.y0) and frame.contains(box.x1, box.y1)
        if inside and not any(box.overlaps(other) for other in taken):
            return box
        first = first or (dx, dy, ha, va)
        note.remove()
    dx, dy, ha, va = first
    note = ax.annotate(text, (x, y), xytext=(dx, dy), textcoords="offset points", ha=ha,
                       va=va, fontsize=8, color=colour)
    return note.get_window_extent(renderer)


# -- fluid oracles -------------------------------------------------------------------------------

def _poiseuille(ax, check: dict) -> None:
    cells = np.asarray(check["cells_across"], float)
    error = 100 * np.asarray(check["max_relative_error"])
    orders = ", ".join(f"{p:.2f}" for p in check["observed_order"])
    ax.plot(cells, error, "o-", color="tab:blue",
            label=f"Hagen–Poiseuille, u = G(R² − r²)/4μ\n(observed order {orders})")
    order_guide(ax, np.geomspace(cells[0], cells[-1]), (cells[-1], error[-1]), 2,
                "second order, ∝ h²")
    ax.axhline(100 * POISEUILLE_GOAL, ls="--", color="tab:blue", lw=1,
               label="Hagen–Poiseuille: the test's bound")


def _piston(ax, rows: list[dict]) -> None:
    cells = [row["cells_across"] for row in rows]
    ax.plot(cells, [100 * row["max_relative_error"] for row in rows], "s-",
            color="tab:orange", label="piston, p = ρ(g + a)h")
    ax.plot(cells, [100 * row["max_error_of_added_mass_part"] for row in rows], "s--",
            mfc="white", color="tab:orange", label="piston, its added-mass part ρah")
    ax.axhline(100 * PISTON_GOAL, ls="--", color="tab:orange", lw=1,
               label="piston: the test's bound")


def fluid() -> plt.Figure:
    """Hagen–Poiseuille and the accelerated piston: the error against the closed form by grid."""
    data = load("fluid_checks")
    fig, ax = plt.subplots(figsize=(WIDTH, 4.3), layout="constrained")
    _poiseuille(ax, data["poiseuille"])
    _piston(ax, data["piston"])
    ax.set(xscale="log", yscale="log", xlabel="cells across the pipe or cylinder (–)",
           ylabel="largest error against the closed form (%)",
           title="The liquid solver against closed forms, by grid")
    integer_ticks(ax.xaxis, [c["cells_across"] for c in data["piston"]]
                  + data["poiseuille"]["cells_across"])
    log_axis(ax.yaxis, minor_labels=True)
    ax.grid(alpha=0.3, which="both")
    ax.legend(**LEGEND)
    credit(fig, "fluid_checks")
    return fig


# -- membrane oracles ------------------------------------------------------------------------------

CLOSED_FORMS = {
    "small": ("Kirchhoff plate, w0 = q a⁴/64D", "tab:blue", "-"),
    "large": ("large-deflection plate (Roark)", "tab:orange", "--"),
    "hencky": ("Hencky's membrane", "tab:green", "-."),
}


def membrane_plate() -> plt.Figure:
    """The flat clamped diaphragm's centre deflection by load: the three closed forms against
    the shell model on three grids."""
    data = load("plate_estimates")
    loads = np.asarray(data["loads"])
    depth = np.asarray(data["validity"]["depth"])  # the shell's w0 / t on the finest grid
    grids = sorted(data["grid_sizes"])
    thickness = np.median(np.asarray(data["shell_centre_deflection"][str(grids[-1])]) / depth)
    fig, ax = plt.subplots(figsize=(WIDTH, 4.6), layout="constrained")
    for name, (label, colour, style) in CLOSED_FORMS.items():
        ratio = np.asarray(data["validity"]["ratio"][name])
        ax.plot(loads, depth * (1 + ratio), style, color=colour, lw=1.4, label=label)
    for n, marker in zip(grids, ("^", "s", "o")):
        w0 = np.asarray(data["shell_centre_deflection"][str(n)])
        ax.plot(loads, w0 / thickness, marker, color="k", ms=5,
                mfc="k" if n == grids[-1] else "white", label=f"shell model, N = {n}")
    ax.set(xscale="log", yscale="log", ylim=(0.5 * depth.min(), 3 * depth.max()),
           xlabel="uniform load q (Pa)", ylabel="centre deflection / thickness, w0 / t (–)",
           title=f"Flat clamped diaphragm, t = {1e3 * thickness:.3f} mm: "
                 "closed forms against the shell model")
    log_axis(ax.xaxis)
    log_axis(ax.yaxis)
    ax.grid(alpha=0.3, which="both")
    ax.legend(**LEGEND)
    credit(fig, "plate_estimates")
    return fig


STRUCTURE_MODELS = {"shell": ("o", "tab:green"), "xpbd": ("s", "tab:orange"),
                    "thesis": ("^", "tab:red")}


def _grid_rows(model: dict) -> list[tuple[int, dict]]:
    """(N, row) of a structure_convergence model by N, without the reference itself (whose
    difference from itself is zero) and without the observed orders."""
    return sorted((int(n), row) for n, row in model.items()
                  if n.isdigit() and row["eqn_6_1_error_percent"] > 1e-6)


def _convergence_series(ax, name: str, rows: list[tuple[int, dict]]) -> None:
    marker, colour = STRUCTURE_MODELS[name]
    ax.plot([n for n, _ in rows], [r["eqn_6_1_error_percent"] for _, r in rows], "-",
            color=colour, lw=1)
    for n, row in rows:
        ax.plot(n, row["eqn_6_1_error_percent"], marker, color=colour, ms=6,
                mfc=colour if row["all_converged"] else "white")
    ax.plot([], [], marker + "-", color=colour, label=f"{name} model")


def membrane_convergence() -> plt.Figure:
    """Each structure model's Eqn 6.1 difference from the reference shape, by grid."""
    data = load("structure_convergence")
    fig, ax = plt.subplots(figsize=(WIDTH, 4.3), layout="constrained")
    for name in STRUCTURE_MODELS:
        _convergence_series(ax, name, _grid_rows(data["models"][name]))
    shell = [(n, r["eqn_6_1_error_percent"]) for n, r in _grid_rows(data["models"]["shell"])]
    order_guide(ax, np.geomspace(shell[0][0], shell[-1][0]), shell[-1], 1,
                "first order, ∝ 1/N")
    ax.plot([], [], "o", color="0.3", mfc="white", label="open: a fill did not converge")
    fills = ", ".join(f"{f:g}" for f in data["tank_fractions"])
    ax.set(xscale="log", yscale="log", xlabel="membrane grid N (nodes per side, –)",
           ylabel=f"Eqn 6.1 difference from\nthe {data['reference']} (%)",
           title=f"Hemispherical diaphragm at tank fractions {fills}, by grid")
    integer_ticks(ax.xaxis, {n for m in STRUCTURE_MODELS
                             for n, _ in _grid_rows(data["models"][m])})
    log_axis(ax.yaxis, minor_labels=True)
    ax.grid(alpha=0.3, which="both")
    ax.legend(**LEGEND)
    credit(fig, "structure_convergence")
    return fig


# -- slosh ---------------------------------------------------------------------------------------

def _slosh_series(ax, data: dict, fill: float, style: dict, label: str) -> None:
    """λ1 by 1/cells for one surface model at one tank fraction, with its extrapolation to 0."""
    cases = sorted((c for c in data["cases"] if c["fill"] == fill), key=lambda c: c["cells"])
    ax.plot([1 / c["cells"] for c in cases], [c["lambda1"] for c in cases], label=label,
            **style)
    for row in data["extrapolated"]:
        if row["fill"] == fill:
            ax.plot(0, row["lambda1"], style["marker"], mfc="white", mec=style["color"], ms=8)


def _slosh_panel(ax, fill: float, reference: float, limp: dict, linear: dict) -> None:
    colour = FILL_COLOURS.get(fill, "tab:blue")
    ax.axhline(reference, label="reference λ1", **REFERENCE)
    ax.axhspan(reference * (1 - SLOSH_BAND), reference * (1 + SLOSH_BAND), color="0.88",
               zorder=0, label=f"reference ± {SLOSH_BAND:.0%}")
    _slosh_series(ax, limp, fill, dict(marker="o", color=colour, ls="-"), "moving surface")
    _slosh_series(ax, linear, fill, dict(marker="s", color=colour, ls="--", mfc="white"),
                  "linearised surface")
    cells = sorted({c["cells"] for c in limp["cases"] if c["fill"] == fill}, reverse=True)
    ax.set_xticks([0] + [1 / c for c in cells], ["0"] + [f"1/{c}" for c in cells],
                  fontsize=8.5)
    ax.set(xlabel="1 / cells per side (–)", title=f"tank fraction {fill:g}")
    ax.set_xlim(-0.006, 1.12 / min(cells))
    ax.grid(alpha=0.3)


def slosh() -> plt.Figure:
    """The sphere's first lateral mode by grid, moving and linearised surface, against the
    reference λ1 (the modes rung's 8-digit value; Budiansky's 1.5602 at half fill)."""
    limp, linear = load("slosh_frequency"), load("slosh_frequency_linear")
    reference = load("sphere_slosh_reference")["fills"]
    fills = sorted({c["fill"] for c in limp["cases"]})
    fig, axes = plt.subplots(1, len(fills), figsize=(WIDTH + 0.6, 4.4), layout="constrained")
    for ax, fill in zip(axes, fills):
        _slosh_panel(ax, fill, reference[f"{fill:g}"]["lambda1"], limp, linear)
    axes[0].set_ylabel("λ1 = ω² R / g (–)")
    handles, labels = axes[0].get_legend_handles_labels()
    handles.append(plt.Line2D([], [], marker="o", color="0.3", mfc="white", ls="", ms=8))
    labels.append("at 0: Richardson, order 2")
    labels[0] += f" (Budiansky's {limp['anchor_lambda1_half']} at half fill)"
    fig.legend(handles, labels, loc="outside upper center", ncols=3, fontsize=8)
    credit(fig, "slosh_frequency", "slosh_frequency_linear", "sphere_slosh_reference")
    return fig


# -- coupling -------------------------------------------------------------------------------------

def _added_mass_panel(ax, data: dict, diaphragm: dict) -> None:
    rows = data["per_mass_ratio"]
    ratio = np.array([r["mass_ratio"] for r in rows])
    # the bound 2 ρs h / (ρs h + ρf μ_max) = 2 / (1 + mass ratio), as the JSON's own values
    if not np.allclose([r["omega_max_predicted"] for r in rows], 2 / (1 + ratio), rtol=1e-9):
        raise ValueError("added_mass.json: omega_max_predicted is not 2 / (1 + mass_ratio)")
    dense = np.geomspace(ratio.min() / 1.5, 2.5 / diaphragm["predicted"]["mass_ratio"])
    ax.plot(dense, 2 / (1 + dense), label="bound 2 ρs·h / (ρs·h + ρf·μ_max)\n"
                                          "(Causin, Gerbeau & Nobile 2005)", **REFERENCE)
    ax.plot(ratio, [r["omega_max_expected_500_iterations"] for r in rows], ":", color="0.3",
            label="the bound for 500 iterations")
    ax.plot(ratio, [r["omega_max_measured"] for r in rows], "o", color="tab:blue",
            label="channel: largest stable ω")
    _diaphragm_stability(ax, diaphragm)
    ax.set(xscale="log", yscale="log", xlabel="mass ratio ρf·μ_max / (ρs·h) (–)",
           ylabel="largest stable constant\nrelaxation ω (–)",
           title="Constant relaxation against the added-mass bound")
    log_axis(ax.xaxis)
    log_axis(ax.yaxis, minor_labels=True)
    ax.grid(alpha=0.3, which="both")
    ax.legend(**LEGEND)


def _diaphragm_stability(ax, data: dict) -> None:
    """The Table 4.1 diaphragm: its estimate (on the bound) and the measured ω bracket."""
    x = 1 / data["predicted"]["mass_ratio"]
    low, high = data["largest_converging_omega"], data["smallest_diverging_omega"]
    ax.plot(x, data["predicted"]["omega_max"], "D", color="tab:red", mfc="white",
            label="diaphragm: the estimate (μ_max = R)")
    ax.plot([x, x], [low, high], "-", color="tab:red", lw=2)
    ax.plot(x, low, "o", color="tab:red", label=f"diaphragm: converges at ω = {low:g}")
    ax.plot(x, high, "x", color="tab:red", ms=8, mew=2,
            label=f"diaphragm: diverges at ω = {high:g}")


def _coupled_fill_panel(ax, data: dict) -> None:
    rows = sorted(data["grids"], key=lambda r: r["cells"])
    cells = np.array([r["cells"] for r in rows], float)
    fluid_part = 100 * np.array([r["fluid_volume_departure"] for r in rows])
    membrane = 100 * np.array([r["membrane_volume_departure"] for r in rows])
    ax.plot(cells, fluid_part, "o-", color="tab:blue", label="the fluid's cut-cell volume")
    ax.plot(cells, membrane, "s-", color="tab:orange", label="the membrane's volume")
    order_guide(ax, np.geomspace(cells[0], cells[-1]), (cells[-1], fluid_part[-1]), 2,
                "second order, ∝ h²")
    ax.set(xscale="log", yscale="log", xlabel="fluid cells per side (–)",
           ylabel="change against the port's\ndelivered volume (%)",
           title=f"Coupled fill, first {rows[0]['windows']} windows: volumes by fluid grid")
    integer_ticks(ax.xaxis, cells)
    log_axis(ax.yaxis, minor_labels=True)
    ax.grid(alpha=0.3, which="both")
    ax.legend(**LEGEND)


def coupling_stability() -> plt.Figure:
    """The added-mass bound against the measured stability of constant relaxation, on the
    channel and on the diaphragm."""
    fig, ax = plt.subplots(figsize=(WIDTH, 4.4), layout="constrained")
    _added_mass_panel(ax, load("added_mass"), load("diaphragm_stability"))
    credit(fig, "added_mass", "diaphragm_stability")
    return fig


def coupled_fill() -> plt.Figure:
    """The coupled fill's liquid volumes against the port's delivered volume, by fluid grid."""
    fig, ax = plt.subplots(figsize=(WIDTH, 4.0), layout="constrained")
    _coupled_fill_panel(ax, load("coupled_fill"))
    credit(fig, "coupled_fill")
    return fig


# -- static against dynamic -------------------------------------------------------------------

CASE_MARKERS = "ovDs^P<>"


def _case_points(ax, cases: dict, x: str, y: str) -> None:
    """One point per case, each case its own marker and colour (named in the first legend)."""
    for k, (name, case) in enumerate(cases.items()):
        ax.plot(case[x], case[y], CASE_MARKERS[k % len(CASE_MARKERS)], color=f"C{k}", ms=7,
                label="case: " + name.replace("^2", "²"))


def static_vs_dynamic() -> plt.Figure:
    """The coupled runs against the static equilibrium at the same volume: the level against
    the dynamic pressure estimate, the peak stress against the static one, the shape."""
    cases = load("static_vs_dynamic")["cases"]
    fig, axes = plt.subplots(3, 1, figsize=(WIDTH, 10.5), layout="constrained")
    level, stress, shape = axes
    p = np.array([c["dynamic_pressure"] for c in cases.values()])
    line = np.geomspace(p.min() / 3, p.max() * 3)
    level.plot(line, line, label="level = p_dyn (the estimate)", **REFERENCE)
    _case_points(level, cases, "dynamic_pressure", "level_difference")
    level.set(xscale="log", yscale="log", xlabel="estimated dynamic pressure p_dyn (Pa)",
              ylabel="level above the\nstatic one (Pa)",
              title="Pressure level against the estimate p_dyn")
    stress.axhline(1, label="the static model", **REFERENCE)
    _case_points(stress, cases, "pressure_ratio", "stress_ratio")
    stress.set(xscale="log", xlabel="Π_p = p_dyn / (ρ g R) (–)",
               ylabel="peak sheet stress,\ndynamic / static (–)",
               title="Peak stress against the static model's at the same volume")
    _case_points(shape, cases, "pressure_ratio", "eqn_6_1")
    shape.set(xscale="log", yscale="log", xlabel="Π_p = p_dyn / (ρ g R) (–)",
              ylabel="Eqn 6.1 difference from\nthe static shape (%)",
              title="Shape against the static model's at the same volume")
    for ax in axes:
        log_axis(ax.xaxis)
        if ax.get_yscale() == "log":
            log_axis(ax.yaxis)
        ax.grid(alpha=0.3, which="both")
        ax.margins(x=0.1, y=0.15)
    level.legend(**LEGEND)
    handles, labels = stress.get_legend_handles_labels()
    stress.legend(handles[:1], labels[:1], **LEGEND)  # the cases are named above
    fig.suptitle("Coupled runs against the static equilibrium holding the same volume",
                 fontsize=11)
    credit(fig, "static_vs_dynamic")
    return fig


# -- performance: speed against accuracy ------------------------------------------------------

def _structure_speed(ax, data: dict) -> list:
    """The hemisphere's statics: each model's sweep time against its difference from the
    reference shape; the thesis's MATLAB time as a line. Returns the points to label."""
    points = []
    for name, (marker, colour) in STRUCTURE_MODELS.items():
        rows = _grid_rows(data["models"][name])
        ax.plot([r["sweep_seconds"] for _, r in rows],
                [r["eqn_6_1_error_percent"] for _, r in rows], "-", color=colour, lw=0.8)
        for n, r in rows:
            ax.plot(r["sweep_seconds"], r["eqn_6_1_error_percent"], marker, color=colour,
                    mfc=colour if r["all_converged"] else "white")
            points.append((r["sweep_seconds"], r["eqn_6_1_error_percent"], f"N={n}", colour))
        ax.plot([], [], marker + "-", color=colour, label=f"{name} model")
    anchor = data["anchor"]["thesis_seconds_N26"]
    ax.axvline(anchor, color="tab:red", ls="--", lw=1.2,
               label=f"the thesis's MATLAB: one\ninversion, N = 26, {anchor / 3600:.1f} h\n"
                     "(its error not published)")
    ax.plot([], [], "o", color="0.3", mfc="white", label="open: a fill\ndid not converge")
    ax.set(xscale="log", yscale="log", xlabel="wall time of a sweep of three fills (s)",
           ylabel=f"Eqn 6.1 difference from\nthe {data['reference']} (%)",
           title="(a) Hemispherical diaphragm, static fill to tank fractions "
                 + ", ".join(f"{f:g}" for f in data["tank_fractions"]))
    log_axis(ax.yaxis, minor_labels=True)
    return points


def _plate_speed(ax, data: dict) -> list:
    """The flat diaphragm per load: closed forms, shell grids and Newton against the shell on
    the finest grid (a line at its own time). Returns the points to label."""
    finest = max(data["grid_sizes"])
    w_ref = np.asarray(data["shell_centre_deflection"][str(finest)])
    seconds = data["seconds_per_load"]
    best = np.min(np.abs([data["validity"]["ratio"][k] for k in CLOSED_FORMS]), axis=0)
    t = seconds["closed_forms"]
    ax.plot([t, t], [100 * best.min(), 100 * best.max()], "-", color="tab:blue", lw=4,
            alpha=0.35, label="closed forms, the best of\nthree: range over the loads")
    points = [(t, 100 * best.max(), f"closed forms, worst load ({best.max():.1%})", "tab:blue"),
              (t, 100 * best.min(), f"closed forms, best load ({best.min():.2%})", "tab:blue")]
    ax.plot([t, t], [100 * best.min(), 100 * best.max()], "v", color="tab:blue")
    for n in sorted(data["grid_sizes"])[:-1]:
        error = np.abs(np.asarray(data["shell_centre_deflection"][str(n)]) / w_ref - 1).max()
        ax.plot(seconds[f"shell_N{n}"], 100 * error, "o", color="tab:green")
        points.append((seconds[f"shell_N{n}"], 100 * error, f"shell, N={n}", "tab:green"))
    newton = data["newton"]
    ax.plot(newton["seconds_per_load"], 100 * newton["max_relative_w0_difference"], "s",
            color="tab:orange")
    points.append((newton["seconds_per_load"], 100 * newton["max_relative_w0_difference"],
                   f"Newton, N={newton['grid_size']}", "tab:orange"))
    ax.axvline(seconds[f"shell_N{finest}"], label=f"the reference: shell\n(L-BFGS), N = {finest}",
               **REFERENCE)
    loads = data["loads"]
    ax.set(xscale="log", yscale="log", xlabel="wall time per load (s)",
           ylabel=f"largest centre-deflection\nerror against the reference (%)",
           title=f"(b) Flat clamped diaphragm, {len(loads)} loads "
                 f"from {loads[0]:g} Pa to {loads[-1]:g} Pa")
    log_axis(ax.yaxis, minor_labels=False)
    return points


def _half_fill(rows: list[dict]) -> list[dict]:
    return [row for row in rows if row["fill"] == 0.5]


def _slosh_series_points(ax, rows: list[tuple[str, float, float]], colour: str, marker: str,
                         label: str) -> list:
    """One method's half-fill runs: a line through them, a legend entry, the points to label."""
    ax.plot([s for _, s, _ in rows], [100 * e for _, _, e in rows], marker + "-", color=colour,
            lw=0.8, label=label)
    return [(s, 100 * e, text, colour) for text, s, e in rows]


def _slosh_speed(ax) -> list:
    """The half-full sphere's λ1: time domain, modes rung and interFoam against the reference.
    Returns the points to label."""
    modes = load("modes_by_fill")
    reference = modes["reference"]["0.5"]["lambda1"]

    def error(lam: float) -> float:
        return abs(lam / reference - 1)

    points = []
    for name, colour, marker in (("slosh_frequency", "tab:blue", "o"),
                                 ("slosh_frequency_linear", "tab:cyan", "s")):
        data = load(name)
        rows = [(f"{c['cells']}³", c["seconds_five_periods"], error(c["lambda1"]))
                for c in _half_fill(data["cases"])]
        rows += [("Richardson", r["seconds_five_periods"], error(r["lambda1"]))
                 for r in _half_fill(data["extrapolated"])]
        surface = "moving" if name == "slosh_frequency" else "linearised"
        points += _slosh_series_points(ax, rows, colour, marker,
                                       f"time domain, {surface} surface")
    faces = [(f"{c['cells']}³", c["seconds_five_periods"], error(c["lambda1"]))
             for c in _half_fill(load("slosh_frequency_faces")["cases"])]
    points += _slosh_series_points(ax, faces, "tab:purple", "D",
                                   "moving surface, level on cell faces")
    cases = sorted(_half_fill(modes["cases"]), key=lambda c: c["cells"])
    rung = [(f"{c['cells']}³", c["wall_seconds"], error(c["lambda1"])) for c in cases]
    rung.append(("Richardson", sum(c["wall_seconds"] for c in cases),
                 error(modes["extrapolated"]["0.5"]["lambda1"])))
    points += _slosh_series_points(ax, rung, "tab:green", "^", "the modes rung")
    peer = load("slosh_frequency")["interfoam"]
    ax.plot(peer["seconds_five_periods"], 100 * abs(peer["lambda1_error"]), "*", ms=13,
            color="tab:red", label=f"OpenFOAM interFoam, {peer['cells']:,} cells")
    points.append((peer["seconds_five_periods"], 100 * abs(peer["lambda1_error"]),
                   "interFoam", "tab:red"))
    ax.set(xscale="log", yscale="log", xlabel="wall time (s): five periods, or the modes solve",
           ylabel=f"|λ1 error| against\nλ1 = {reference:.7g} (%)",
           title="(c) Half-full sphere: the first slosh mode λ1")
    log_axis(ax.yaxis, minor_labels=False)
    return points


def performance_speed_accuracy() -> plt.Figure:
    """Wall time against error for the statics of both diaphragms and for the slosh mode, with
    the peers (the thesis's MATLAB, OpenFOAM's interFoam)."""
    fig, axes = plt.subplots(3, 1, figsize=(WIDTH, 12.5), layout="constrained")
    panels = [(_structure_speed, (load("structure_convergence"),)),
              (_plate_speed, (load("plate_estimates"),)), (_slosh_speed, ())]
    labels = [draw(ax, *args) for ax, (draw, args) in zip(axes, panels)]
    for ax in axes:
        log_axis(ax.xaxis)
        ax.grid(alpha=0.3, which="both")
        ax.margins(x=0.25, y=0.25)
        ax.legend(**LEGEND)
    fig.suptitle("Speed against accuracy on this machine (2 cores): lower left is better",
                 fontsize=11)
    credit(fig, "structure_convergence", "plate_estimates", "slosh_frequency",
           "slosh_frequency_linear", "slosh_frequency_faces", "modes_by_fill")
    for ax, points in zip(axes, labels):
        label_points(fig, ax, points)
    return fig


# -- the shell of revolution ------------------------------------------------------------------

def shell_of_revolution() -> plt.Figure:
    """The Table 4.1 diaphragm as a shell of revolution: the level along the fill and the
    drain with the snaps and the onset of folding, and the fill's stability by wave number."""
    data = load("diaphragm_axisymmetric")
    rows = data["fills"]
    f = np.array([r["tank_fraction"] for r in rows])
    fig, (a, b) = plt.subplots(1, 2, figsize=(WIDTH + 0.6, 4.2), layout="constrained")
    a.plot(f, [r["level_fill"] for r in rows], "o-", ms=3, label="fill")
    a.plot(f, [r["level_drain"] for r in rows], "s--", ms=4, mfc="none", label="drain")
    for snap in data["snaps"]:
        a.plot([snap["tank_fraction"]] * 2, [snap["level_before"], snap["level_after"]], "k:",
               lw=1)
    a.plot([], [], "k:", lw=1, label="snaps")
    onset = data["onset"]
    a.axvline(onset["tank_fraction"], color="tab:red", lw=1,
              label=f"onset of folding, {onset['lobes']} lobes")
    a.set(xlabel="tank fraction V / (4/3 π R³) (–)", ylabel="pressure level p_ref (Pa)",
          title=f"Fill and drain, {data['elements']} elements")
    a.grid(alpha=0.3)
    a.legend(fontsize=8, loc="upper left")
    stab = data["stability_map"]
    waves = np.array(stab["wave_numbers"])
    values = np.array([[np.nan] * len(waves) if v is None else v for v in stab["fill"]]).T
    mesh = b.pcolormesh(f, waves, np.sign(values), cmap="RdBu", vmin=-1.6, vmax=1.6,
                        shading="nearest")
    b.plot(onset["tank_fraction"], onset["lobes"], "k*", ms=11,
           label=f"onset: n = {onset['lobes']} at {onset['tank_fraction']:.4f}")
    b.set(xlabel="tank fraction (–)", ylabel="circumferential wave number n (–)",
          title="Fill: stable (blue) or unstable (red) to n lobes")
    b.legend(fontsize=8, loc="upper right")
    del mesh
    credit(fig, "diaphragm_axisymmetric")
    return fig


FIGURES: dict[str, Callable[[], plt.Figure]] = {
    "fluid": fluid,
    "membrane_plate": membrane_plate,
    "membrane_convergence": membrane_convergence,
    "slosh": slosh,
    "coupling_stability": coupling_stability,
    "coupled_fill": coupled_fill,
    "static_vs_dynamic": static_vs_dynamic,
    "shell_of_revolution": shell_of_revolution,
    "performance_speed_accuracy": performance_speed_accuracy,
}


def main(names: list[str]) -> list[Path]:
    unknown = sorted(set(names) - set(FIGURES))
    if unknown:
        raise SystemExit(f"unknown figure(s) {', '.join(unknown)}; known: {', '.join(FIGURES)}")
    return [save(FIGURES[name](), name) for name in names or FIGURES]


if __name__ == "__main__":
    for path in main(sys.argv[1:]):
        print(path)
