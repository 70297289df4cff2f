"""The diaphragm's stress plots, for every result with membrane frames (``envelope``):

* ``stress_envelope.png``: each triangle's peak stress over the run
  (:mod:`fsi.analysis.envelope`) on the rest shape unrolled about its pole (radius: the rest
  polar angle, angle: the azimuth), the colour scale to the 99th percentile of the free
  sheet, the run's peak starred and its value written;
* ``peak_stress_frame.png``: the 3-D render (:mod:`fsi.io.render`) of the frame of the run's
  peak, coloured by von Mises stress to the 99th percentile of its free sheet, its largest
  value marked and written; not made (one line says why) where the renderer is missing;
* ``diaphragm_history.png``: against time (or the tank fraction V / (4/3 pi R^3)), the
  largest stress and strain on the free sheet (:func:`structure.topology.free_triangles`),
  the fold count, the wall contact area and the inverted area fraction, with the events as
  ticks.
"""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from fsi.io import render  # noqa: E402
from fsi.io.output import MAIN_GROUP as ENVELOPE_GROUP, frame_stamp as stamp_name  # noqa: E402
from fsi.io.plot_registry import save  # noqa: E402
from structure.grid import triangles_from_quads  # noqa: E402
from structure.topology import free_triangles, rest_angles  # noqa: E402


def stress_plots(res: dict, out: Path) -> list[Path]:
    """The plots of the module doc, or none without an envelope (the 3-D render of the
    peak's frame not where the renderer is missing)."""
    if "envelope" not in res:
        return []
    written = [_envelope_plot(res, out / "stress_envelope.png"),
               _history_plot(res, out / "diaphragm_history.png")]
    if "von_mises_stress" in res[ENVELOPE_GROUP] and render.usable():
        written.append(_peak_frame_plot(res, out / "peak_stress_frame.png"))
    return written


TOP_PERCENTILE = 99.0
"""The colour scales of the stress plots end at this percentile of the free sheet's values,
so that a few peak triangles do not wash the rest of the sheet out."""
TANK_FRACTION = "tank fraction V / (4/3 $\\pi$ R$^3$)"
"""How an axis or a colourbar names the fill."""


def _unrolled(res: dict) -> np.ndarray:
    rest = res["membrane"]["rest_position"]
    radius = float(res["attrs"]["radius"])
    polar, azimuth = rest_angles(rest, radius, bool(np.ptp(rest[:, 2]) == 0))
    phi = np.radians(azimuth)
    return np.column_stack([polar * np.cos(phi), polar * np.sin(phi)])


def _sheet(res: dict) -> np.ndarray:
    """(m,) bool, the free sheet's triangles."""
    return free_triangles(res["membrane"]["fixed"],
                          triangles_from_quads(res["membrane"]["face_nodes"]))


def _colour_map():
    """The sheet's colour map (:data:`fsi.io.render.CMAP`), values above the scale in
    :data:`fsi.io.render.ABOVE_COLOUR` as in the 3-D renders."""
    return plt.get_cmap(render.CMAP).with_extremes(over=render.ABOVE_COLOUR)


def _envelope_plot(res: dict, path: Path) -> Path:
    """Each triangle's peak principal stress over the run on the unrolled rest shape, the
    colour scale to the 99th percentile of the free sheet, the run's peak starred."""
    a, env = res["attrs"], res["envelope"]
    tri = triangles_from_quads(res["membrane"]["face_nodes"])
    flat = _unrolled(res)
    stress = env["peak_stress"] / 1e6
    top = render.percentile_scale(stress[_sheet(res)], TOP_PERCENTILE)[1]
    fig, ax = plt.subplots(figsize=(7, 5.6))
    shade = ax.tripcolor(flat[:, 0], flat[:, 1], tri, facecolors=stress, cmap=_colour_map(),
                         vmin=0.0, vmax=top, edgecolors="none")
    fig.colorbar(shade, ax=ax, extend="max",
                 label="peak principal stress over the run (MPa)")
    phi = np.radians(a["peak_stress_azimuth_deg"])
    peak = a["peak_stress"] / 1e6
    ax.plot(a["peak_stress_polar_deg"] * np.cos(phi), a["peak_stress_polar_deg"] * np.sin(phi),
            "*", color=render.MARK_COLOUR, ms=16, mec="k",
            label=f"peak {peak:.3g} MPa (colour scale to the {TOP_PERCENTILE:.0f}th "
                  f"percentile, {top:.3g} MPa)")
    ax.set_aspect("equal")
    ax.set_xlabel("polar angle x cos(azimuth) (deg)")
    ax.set_ylabel("polar angle x sin(azimuth) (deg)")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), fontsize=9, frameon=False)
    ax.set_title("Stress envelope on the rest shape (pole at the centre)", fontsize=10)
    return save(fig, path)


def _peak_frame(res: dict) -> int:
    """The main group's frame of the run's peak stress (the largest ``surface_stress`` of
    the free sheet)."""
    stress = res[ENVELOPE_GROUP]["surface_stress"][:, _sheet(res)]
    return int(np.argmax(np.where(np.isfinite(stress), stress, -np.inf).max(axis=1)))


def _when(frames: dict, k: int) -> str:
    return f"t = {frames['time'][k]:.4g} s" if stamp_name(frames) == "time" else \
        f"tank fraction {frames['tank_fraction'][k]:.3f}"


def _peak_frame_plot(res: dict, path: Path) -> Path:
    """The 3-D render of the frame of the run's peak stress, coloured by von Mises stress
    up to the 99th percentile of the frame's free sheet, its largest value marked, seen
    from where the sheet does not hide it."""
    k = _peak_frame(res)
    frame = render.frame_of(res, ENVELOPE_GROUP, k)
    top = render.percentile_scale(render.sheet_values(frame, "von_mises"), TOP_PERCENTILE)
    point, peak = render.peak_point(frame, "von_mises")
    view = render.View(
        frame, "von_mises", top,
        title=f"Frame of the run's peak stress, {_when(res[ENVELOPE_GROUP], k)}",
        note=f"largest von Mises stress here {peak:.3g} MPa (colour scale to the "
             f"{TOP_PERCENTILE:.0f}th percentile, {top[1]:.3g} MPa); the run's peak principal "
             f"stress {res['attrs']['peak_stress'] / 1e6:.3g} MPa",
        mark=render.Mark(point, f"von Mises {peak:.3g} MPa"),
        camera=render.camera_seeing(frame, point))
    with render.Renderer() as renderer:
        return renderer.save(view, path)


def _tank_fraction_at(frames: dict, stamps: np.ndarray) -> np.ndarray:
    """The tank fraction of the frames stamped ``stamps`` (the frames' own stamp)."""
    own = np.asarray(frames[stamp_name(frames)], dtype=float)
    nearest = np.argmin(np.abs(own[None, :] - np.asarray(stamps, dtype=float)[:, None]), axis=1)
    return np.asarray(frames["tank_fraction"], dtype=float)[nearest]


HISTORY_AXES = {"time": ("time", "time (s)"), "fill": ("tank_fraction", TANK_FRACTION)}
"""A run in time or a fill: the per-frame dataset of the history's x axis and its label."""


def _history_plot(res: dict, path: Path) -> Path:
    frames, events = res[ENVELOPE_GROUP], res.get("events", {})
    stamp = stamp_name(frames)
    name, x_label = HISTORY_AXES["time" if stamp == "time" else "fill"]
    x = np.asarray(frames[name], dtype=float)
    fig, axes = plt.subplots(4, 1, figsize=(7, 8), sharex=True)
    sheet = _sheet(res)
    axes[0].plot(x, np.max(frames["surface_stress"][:, sheet], axis=1) / 1e6, "k-o", ms=3)
    axes[0].set_ylabel("largest stress\n(MPa)")
    strain = axes[0].twinx()
    strain.plot(x, np.max(frames["log_strain"][:, sheet, 0], axis=1), "C1--", lw=1)
    strain.set_ylabel("largest log strain", color="C1")
    axes[1].step(x, frames["fold_count"], "k-", where="post")
    axes[1].set_ylabel("folds")
    axes[2].plot(x, frames["wall_contact_area"], "k-o", ms=3)
    axes[2].set_ylabel("wall contact\n(m$^2$)")
    axes[3].plot(x, frames["inverted_area_fraction"], "k-o", ms=3)
    axes[3].set_ylabel("inverted\narea fraction")
    axes[3].set_xlabel(x_label)
    ticks = np.asarray(events.get(stamp, []), dtype=float)
    if name != stamp and ticks.size:
        ticks = _tank_fraction_at(frames, ticks)
    for t in ticks:
        for ax in axes:
            ax.axvline(t, color="0.8", lw=0.6, zorder=0)
    axes[0].set_title(f"The diaphragm through the run ({len(events.get('event', []))} events, "
                      "grey lines)", fontsize=10)
    return save(fig, path)
