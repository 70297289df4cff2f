"""Envelopes of a run's membrane frames: per triangle, the largest stress and strain and when.

Over the frames of one group (the main sequence, :data:`fsi.io.output.MAIN_GROUP`), stamped
by ``time`` (s) or, for a static sweep, by ``tank_fraction``:

- ``peak_stress`` (m,) Pa: the largest principal stress over the two surfaces
  (``surface_stress``), and ``peak_stress_<stamp>`` when it occurred;
- ``peak_strain`` (m,) 1: the largest principal logarithmic strain, and
  ``peak_strain_<stamp>``;
- ``polar_deg`` and ``azimuth_deg`` (m,): where each triangle is on the rest shape
  (:func:`structure.topology.rest_angles`).

The run's peak of each over the free sheet (the triangles with a free node: on the thesis's
grid the two support rings are the clamp, whose triangles' bending is the clamp's), with its
place and stamp, goes in the result's attributes (:func:`peak_attributes`).
"""
from __future__ import annotations

import numpy as np

from fsi.io.output import frame_stamp as stamp_name


def envelope(group: dict, polar: np.ndarray, azimuth: np.ndarray) -> dict:
    """The envelope datasets (module doc) of ``group``'s frames, which carry
    ``surface_stress`` and ``log_strain``; ``polar``, ``azimuth`` (m,) deg."""
    stamp = stamp_name(group)
    at = np.asarray(group[stamp], dtype=float)
    out = dict(polar_deg=polar, azimuth_deg=azimuth)
    for name, series in (("peak_stress", group["surface_stress"]),
                         ("peak_strain", group["log_strain"][:, :, 0])):
        series = np.asarray(series, dtype=float)
        series = np.where(np.isfinite(series), series, -np.inf)   # a failed frame's: missing
        k = np.argmax(series, axis=0)
        out[name] = series[k, np.arange(series.shape[1])]
        out[name][~np.isfinite(out[name])] = np.nan
        out[f"{name}_{stamp}"] = at[k]
    return out


def peak_attributes(env: dict, stamp: str, sheet: np.ndarray) -> dict:
    """The run's peak stress and strain over the triangles ``sheet`` (m,) bool (those of
    the free sheet: a triangle between two support rings is inside the clamp), each with
    its ``_triangle`` (index), rest ``_polar_deg``, ``_azimuth_deg`` and its ``_<stamp>``,
    from an :func:`envelope`."""
    out = {}
    for name in ("peak_stress", "peak_strain"):
        t = int(np.argmax(np.where(sheet & np.isfinite(env[name]), env[name], -np.inf)))
        out.update({name: float(env[name][t]), f"{name}_triangle": t,
                    f"{name}_{stamp}": float(env[f"{name}_{stamp}"][t]),
                    f"{name}_polar_deg": float(env["polar_deg"][t]),
                    f"{name}_azimuth_deg": float(env["azimuth_deg"][t])})
    return out
