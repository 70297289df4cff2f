"""Topology events of a run's membrane frames: each change of state is one row.

From the per-frame topology series of :mod:`fsi.analysis.membrane_fields` and each frame's
folds (clusters of triangles):

- ``fold forms`` / ``fold vanishes``: a fold with no triangle in common with any fold of the
  frame before (after); its place is the rest centroid of its triangles (area-weighted) and
  its ``area`` the rest area of its triangles (m^2);
- ``wall contact starts`` / ``ends``: ``wall_contact_area`` leaves / returns to zero;
- ``self-contact starts`` / ``ends``: ``self_contact_nodes`` leaves / returns to zero;
- ``inversion starts`` / ``ends``: ``inverted_area_fraction`` leaves / returns to zero.

The rows (group ``events``): the stamp of the frame where the new state is first seen
(``time`` s, or ``tank_fraction``), ``event`` (text), ``polar_deg`` and ``azimuth_deg`` (the
place, NaN where the event has none) and ``area`` (m^2: the fold's, the contact's, or the
inverted fraction times the sheet's free rest area).
"""
from __future__ import annotations

import numpy as np

STATE_SERIES = {"wall_contact_area": "wall contact", "self_contact_nodes": "self-contact",
                "inverted_area_fraction": "inversion"}
"""Per-frame series whose zero / non-zero state changes are events -> the event's name."""


def _place(cluster: np.ndarray, area: np.ndarray, polar: np.ndarray, azimuth: np.ndarray):
    w = area[cluster]
    phi = np.radians(azimuth[cluster])
    mean_azimuth = np.degrees(np.arctan2(w @ np.sin(phi), w @ np.cos(phi))) % 360.0
    return float(w @ polar[cluster] / w.sum()), float(mean_azimuth), float(w.sum())


def topology_events(stamp: np.ndarray, series: dict, folds: list, area: np.ndarray,
                    polar: np.ndarray, azimuth: np.ndarray, free_area: float) -> dict:
    """The event rows (module doc) of frames stamped ``stamp`` (f,), with ``series``
    {name: (f,)} and ``folds`` (f lists of triangle index arrays); ``area``, ``polar``,
    ``azimuth`` (m,) the triangles' rest area (m^2) and place (deg); ``free_area`` (m^2) the
    free sheet's rest area. Returns {"event": (e,) bytes, "at": (e,), "polar_deg",
    "azimuth_deg", "area": (e,)}."""
    rows = []
    for k in range(1, len(stamp)):
        before, now = folds[k - 1], folds[k]
        seen_before = set(np.concatenate(before).tolist()) if before else set()
        seen_now = set(np.concatenate(now).tolist()) if now else set()
        for cluster in now:
            if seen_before.isdisjoint(cluster.tolist()):
                rows.append((stamp[k], "fold forms", *_place(cluster, area, polar, azimuth)))
        for cluster in before:
            if seen_now.isdisjoint(cluster.tolist()):
                rows.append((stamp[k], "fold vanishes", *_place(cluster, area, polar, azimuth)))
        for name, label in STATE_SERIES.items():
            a, b = series[name][k - 1], series[name][k]
            if np.isnan(a) or np.isnan(b) or (a > 0) == (b > 0):
                continue
            size = float(b if name != "self_contact_nodes" else np.nan)
            if name == "inverted_area_fraction":
                size = float(b * free_area)
            rows.append((stamp[k], f"{label} {'starts' if b > 0 else 'ends'}", np.nan, np.nan,
                         size))
    return dict(at=np.array([r[0] for r in rows], dtype=float),
                event=np.array([r[1] for r in rows], dtype="S24"),
                polar_deg=np.array([r[2] for r in rows], dtype=float),
                azimuth_deg=np.array([r[3] for r in rows], dtype=float),
                area=np.array([r[4] for r in rows], dtype=float))
