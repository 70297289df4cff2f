"""The diaphragm's stress plots, for every result with membrane frames (``envelope``):

* ``stress_envelope.png``: left, each triangle's peak stress over the run
  (:mod:`fsi.analysis.envelope`) on the rest shape unrolled about its pole (radius: the rest
  polar angle, angle: the azimuth), the run's peak starred; right, the surface stress of the
  frame of the peak on the deformed sheet;
* ``diaphragm_history.png``: against time (or fill), the largest stress and strain on the
  free sheet (:func:`structure.topology.free_triangles`), the fold count, the wall contact area and the inverted area fraction, with the
  events as ticks.
"""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

from fsi.io.output import MAIN_GROUP as ENVELOPE_GROUP, frame_stamp as stamp_name  # noqa: E402
from fsi.io.plot_registry import save  # noqa: E402
from structure.grid import triangles_from_quads  # noqa: E402
from structure.topology import free_triangles, rest_angles  # noqa: E402


def stress_plots(res: dict, out: Path) -> list[Path]:
    """The two plots of the module doc, or none without an envelope."""
    if "envelope" not in res:
        return []
    return [_envelope_plot(res, out / "stress_envelope.png"),
            _history_plot(res, out / "diaphragm_history.png")]


def _unrolled(res: dict) -> np.ndarray:
    rest = res["membrane"]["rest_position"]
    radius = float(res["attrs"]["radius"])
    polar, azimuth = rest_angles(rest, radius, bool(np.ptp(rest[:, 2]) == 0))
    phi = np.radians(azimuth)
    return np.column_stack([polar * np.cos(phi), polar * np.sin(phi)])


def _envelope_plot(res: dict, path: Path) -> Path:
    a, env, frames = res["attrs"], res["envelope"], res[ENVELOPE_GROUP]
    tri = triangles_from_quads(res["membrane"]["face_nodes"])
    flat = _unrolled(res)
    stamp = stamp_name(frames)
    fig = plt.figure(figsize=(11, 4.8))
    ax = fig.add_subplot(1, 2, 1)
    shade = ax.tripcolor(flat[:, 0], flat[:, 1], tri, facecolors=env["peak_stress"] / 1e6,
                         cmap="viridis", edgecolors="none")
    fig.colorbar(shade, ax=ax, label="peak principal stress over the run (MPa)")
    phi = np.radians(a["peak_stress_azimuth_deg"])
    ax.plot(a["peak_stress_polar_deg"] * np.cos(phi), a["peak_stress_polar_deg"] * np.sin(phi),
            "r*", ms=14, mec="k", label=f"peak {a['peak_stress'] / 1e6:.3g} MPa")
    ax.set_aspect("equal")
    ax.set_xlabel("polar angle x cos(azimuth) (deg)")
    ax.set_ylabel("polar angle x sin(azimuth) (deg)")
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title("Envelope on the rest shape (pole at the centre)", fontsize=10)
    k = int(np.argmin(np.abs(frames[stamp] - a[f"peak_stress_{stamp}"])))
    pos = frames["node_position"][k]
    ax3 = fig.add_subplot(1, 2, 2, projection="3d")
    stress = np.asarray(frames["surface_stress"][k], dtype=float) / 1e6
    colours = plt.get_cmap("viridis")(plt.Normalize(stress.min(), stress.max())(stress))
    ax3.add_collection3d(Poly3DCollection(pos[tri], facecolors=colours, edgecolor="k",
                                          linewidths=0.05))
    radius = float(a["radius"])
    lim = (-radius, radius)
    ax3.set(xlim=lim, ylim=lim, zlim=lim, xlabel="x (m)", ylabel="y (m)", zlabel="z (m)")
    ax3.set_box_aspect((1, 1, 1))
    ax3.view_init(elev=25, azim=45)
    mappable = plt.cm.ScalarMappable(plt.Normalize(stress.min(), stress.max()), "viridis")
    fig.colorbar(mappable, ax=ax3, shrink=0.7, label="surface stress (MPa)")
    when = f"t = {frames[stamp][k]:.4g} s" if stamp == "time" else \
        f"tank fraction {frames['tank_fraction'][k]:.3f}"
    ax3.set_title(f"Stress at the peak's frame, {when}", fontsize=10)
    return save(fig, path)


def _history_plot(res: dict, path: Path) -> Path:
    frames, events = res[ENVELOPE_GROUP], res.get("events", {})
    stamp = stamp_name(frames)
    x = np.asarray(frames[stamp], dtype=float)
    fig, axes = plt.subplots(4, 1, figsize=(7, 8), sharex=True)
    sheet = free_triangles(res["membrane"]["fixed"],
                           triangles_from_quads(res["membrane"]["face_nodes"]))
    axes[0].plot(x, np.max(frames["surface_stress"][:, sheet], axis=1) / 1e6, "k-o", ms=3)
    axes[0].set_ylabel("largest stress\n(MPa)")
    strain = axes[0].twinx()
    strain.plot(x, np.max(frames["log_strain"][:, sheet, 0], axis=1), "C1--", lw=1)
    strain.set_ylabel("largest log strain", color="C1")
    axes[1].step(x, frames["fold_count"], "k-", where="post")
    axes[1].set_ylabel("folds")
    axes[2].plot(x, frames["wall_contact_area"], "k-o", ms=3)
    axes[2].set_ylabel("wall contact\n(m^2)")
    axes[3].plot(x, frames["inverted_area_fraction"], "k-o", ms=3)
    axes[3].set_ylabel("inverted\narea fraction")
    axes[3].set_xlabel("time (s)" if stamp == "time" else "fill fraction")
    for t in np.asarray(events.get(stamp, []), dtype=float):
        for ax in axes:
            ax.axvline(t, color="0.8", lw=0.6, zorder=0)
    axes[0].set_title(f"The diaphragm through the run ({len(events.get('event', []))} events, "
                      "grey lines)", fontsize=10)
    return save(fig, path)
