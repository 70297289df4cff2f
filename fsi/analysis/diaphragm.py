"""What a run did to the diaphragm, added to its result before it is written.

:func:`annotate` adds to every group of membrane frames (``node_position``) the stress, strain
and topology datasets of :mod:`fsi.analysis.membrane_fields`, from the law the run used; and,
over the main sequence (:data:`fsi.io.output.MAIN_GROUP`):

- group ``envelope`` and the peak's attributes (:mod:`fsi.analysis.envelope`); with the
  scene's ``limits.stress`` or ``limits.strain``, ``stress_margin`` or ``strain_margin``, the
  limit over the run's peak (below 1: exceeded); for a run whose
  frames hold the volume of their static start (``holds_volume``: a slosh run), the
  attribute ``dynamic_amplification``, the run's peak stress over the start's (the static
  model at the same volume);
- group ``events``, the topology's changes (:mod:`fsi.analysis.events`);
- for frames in time, group ``cycles``: the rainflow cycles of the most loaded triangles'
  stress, and with the scene's S-N curve the attribute ``miner_damage`` (per run of the
  scene) and ``miner_damage_triangle`` (:mod:`fsi.analysis.fatigue`).
"""
from __future__ import annotations

import logging

import numpy as np

from fsi.analysis.envelope import envelope, peak_attributes, stamp_name
from fsi.analysis.events import topology_events
from fsi.analysis.fatigue import miner_damage, stress_cycles
from fsi.analysis.membrane_fields import (FIELD_RULES, SheetGeometry, group_fields,
                                          invalid_frames)
from fsi.io.output import MAIN_GROUP as ENVELOPE_GROUP

log = logging.getLogger(__name__)


def membrane_groups(result) -> list[str]:
    """The groups of ``result`` that hold membrane frames."""
    return [name for name, g in result.groups.items()
            if "node_position" in g and len(g["node_position"]) > 0]


def cycles_of(group: dict, peak_stress: np.ndarray, sheet: np.ndarray, how_many: int) -> dict:
    """The ``cycles`` group: rainflow cycles of the ``how_many`` triangles of the free sheet
    ``sheet`` (m,) bool of largest ``peak_stress`` (m,) Pa over ``group``'s
    ``surface_stress`` history."""
    rows = []
    for t in np.argsort(np.where(sheet, peak_stress, -np.inf))[::-1][:how_many]:
        history = np.asarray(group["surface_stress"][:, t], dtype=float)
        for r, mean, count in stress_cycles(history[np.isfinite(history)]):
            rows.append((t, r, mean, count))
    a = np.asarray(rows, dtype=float).reshape(-1, 4)
    return dict(triangle=a[:, 0].astype(np.int64), stress_range=a[:, 1], mean_stress=a[:, 2],
                count=a[:, 3])


def annotate(setup, result) -> None:
    """Add the diaphragm's fields, envelope, events and cycles to ``result`` (module doc):
    all of them, or, when any step raises, none."""
    names = membrane_groups(result)
    if not names:
        return
    model = setup.model
    rule = FIELD_RULES[setup.structure_model](model, setup.scene)
    geometry = SheetGeometry.of(model, rule.term.triangles)
    groups, attrs = {}, {"stress_law": rule.law}
    for name in names:
        group = dict(result.groups[name])
        fields, folds = group_fields(rule, geometry, model, group["node_position"])
        group.update(fields)
        groups[name] = group
        if name == ENVELOPE_GROUP:
            groups.update(_over_the_run(setup, geometry, group, fields, folds, attrs))
    failed = invalid_frames(groups)
    if failed:
        attrs["stress_invalid_frames"] = "; ".join(failed)
        log.warning("the stress fields are not finite in %s: those frames' fields are "
                    "written as missing", attrs["stress_invalid_frames"])
    result.groups.update(groups)
    result.attrs.update(attrs)


def _over_the_run(setup, geometry: SheetGeometry, group: dict, fields: dict, folds: list,
                  attrs: dict) -> dict:
    """The envelope, events and cycles groups of the main sequence ``group``; its attributes
    into ``attrs``."""
    stamp = stamp_name(group)
    env = envelope(group, geometry.rest_polar, geometry.rest_azimuth)
    attrs.update(peak_attributes(env, stamp, geometry.free_triangle))
    t = attrs["peak_stress_triangle"]
    k = int(np.nanargmax(fields["surface_stress"][:, t]))    # the frame of the peak
    attrs["peak_stress_membrane"] = float(fields["principal_stress"][k, t, 0])
    for name, peak in (("stress", "peak_stress"), ("strain", "peak_strain")):
        limit = setup.scene["limits"][name]
        if limit > 0:
            attrs[f"{name}_margin"] = float(limit / attrs[peak])
    if setup.procedure.holds_volume:
        start = group["surface_stress"][0][geometry.free_triangle]
        attrs["dynamic_amplification"] = float(attrs["peak_stress"] / np.max(start)) \
            if group["stress_valid"][0] else np.nan
    free_area = float(geometry.node_area[~setup.model.node_fixed].sum())
    events = topology_events(np.asarray(group[stamp], float), fields, folds,
                             geometry.triangle_area, geometry.rest_polar,
                             geometry.rest_azimuth, free_area)
    out = {"envelope": env, "events": {stamp: events.pop("at"), **events}}
    if stamp != "time":
        return out
    fatigue = setup.scene["fatigue"]
    cycles = cycles_of(group, env["peak_stress"], geometry.free_triangle,
                       fatigue["peak_triangles"])
    out["cycles"] = cycles
    if fatigue["sn_curve"]:
        triangles = np.unique(cycles["triangle"])
        table = np.column_stack([cycles["stress_range"], cycles["mean_stress"],
                                 cycles["count"]])
        damage = [miner_damage(table[cycles["triangle"] == t], fatigue["sn_curve"])
                  for t in triangles]
        worst = int(np.argmax(damage))
        attrs.update(miner_damage=float(damage[worst]),
                     miner_damage_triangle=int(triangles[worst]))
    return out


def summary_lines(res: dict) -> list[str]:
    """What ``fsi show`` says of the diaphragm of a read result (:func:`fsi.io.output.
    read_result`): the peak stress and strain with their place and stamp, the folds and
    the events, the largest stress cycles and Miner's damage; none without membrane
    frames."""
    a = res["attrs"]
    if a.get("stress_analysis_failure"):
        return [f"  stress: not analysed ({a['stress_analysis_failure']})"]
    if "peak_stress" not in a:
        return []
    stamp = "time" if "peak_stress_time" in a else "tank_fraction"
    unit = " s" if stamp == "time" else ""
    label = "t =" if stamp == "time" else "tank fraction"

    def peak(name, value):
        return (f"{value} at polar {a[f'{name}_polar_deg']:.1f} deg, azimuth "
                f"{a[f'{name}_azimuth_deg']:.1f} deg, {label} {a[f'{name}_{stamp}']:.4g}{unit}")

    amplification = (f"; x {a['dynamic_amplification']:.3g} of the static start's"
                     if "dynamic_amplification" in a else "")
    def margin(name):
        key = f"{name}_margin"
        if key not in a:
            return f"; no limits.{name} in the scene"
        verdict = "EXCEEDED" if a[key] < 1 else "within it"
        return f"; limit / peak = {a[key]:.3g} ({verdict})"

    split = (f" (membrane {a['peak_stress_membrane'] / 1e6:.4g} MPa, the rest bending)"
             if "peak_stress_membrane" in a else "")
    lines = [f"  stress ({a.get('stress_law', '?')}): peak "
             + peak("peak_stress", f"{a['peak_stress'] / 1e6:.4g} MPa{split}") + amplification
             + margin("stress"),
             "  strain: peak log strain " + peak("peak_strain", f"{a['peak_strain']:.4g}")
             + margin("strain")]
    frames = res.get("frames", {})
    if "fold_count" in frames:
        folds = np.asarray(frames["fold_count"])
        contact = np.asarray(frames["wall_contact_area"])
        lines.append(f"  folds: {int(folds.max())} at most ({int(folds[-1])} at the end); wall "
                     f"contact up to {contact.max():.4g} m^2; self-contact in "
                     f"{int(np.count_nonzero(frames['self_contact_nodes']))} frames")
    events = res.get("events", {})
    if "event" in events:
        kinds, counts = np.unique([e.decode() if isinstance(e, bytes) else str(e)
                                   for e in events["event"]], return_counts=True)
        text = ", ".join(f"{k} {c}" for k, c in zip(kinds, counts)) or "none"
        lines.append(f"  events: {len(events['event'])} ({text})")
    cycles = res.get("cycles", {})
    if "stress_range" in cycles and len(cycles["stress_range"]):
        k = int(np.argmax(cycles["stress_range"]))
        damage = (f"Miner damage {a['miner_damage']:.3g} per run (triangle "
                  f"{a['miner_damage_triangle']})" if "miner_damage" in a
                  else "no S-N curve in the scene (fatigue.sn_curve)")
        lines.append(f"  cycles: {len(cycles['stress_range'])} over "
                     f"{len(np.unique(cycles['triangle']))} triangles, largest range "
                     f"{cycles['stress_range'][k] / 1e6:.4g} MPa (count "
                     f"{cycles['count'][k]:g}); {damage}")
    return lines


DATASETS = {
    "<frames>/principal_resultant": ("(f, m, 2)", "principal Cauchy membrane resultants, "
                                     "largest first"),
    "<frames>/principal_direction": ("(f, m, 3)", "unit direction of the first, now"),
    "<frames>/principal_stress": ("(f, m, 2)", "principal mid-surface stresses, resultant / "
                                  "current thickness"),
    "<frames>/bending_stress": ("(f, m, 2)", "principal bending stresses 6 M / t^2 on one "
                                "surface (the other's are their negatives)"),
    "<frames>/surface_stress": ("(f, m)", "largest principal stress of the two surfaces, "
                                "membrane plus bending"),
    "<frames>/von_mises_stress": ("(f, m)", "largest von Mises stress of the two surfaces"),
    "<frames>/green_strain": ("(f, m, 2)", "principal Green-Lagrange strains"),
    "<frames>/log_strain": ("(f, m, 2)", "principal logarithmic strains"),
    "<frames>/thickness": ("(f, m)", "current thickness"),
    "<frames>/stress_valid": ("(f,)", "true where every stress, strain and thickness of the "
                              "frame is finite; a false frame's fields are missing "
                              "(_FillValue) and the run exits 3"),
    "<frames>/fold_count": ("(f,)", "folds: clusters of wrinkled or creased triangles"),
    "<frames>/inverted_area_fraction": ("(f,)", "share of the free sheet across the rim's "
                                        "plane"),
    "<frames>/inversion_front_deg": ("(f,)", "rest polar angle of the cap of that share"),
    "<frames>/wall_contact_area": ("(f,)", "rest area of the free nodes on the tank wall"),
    "<frames>/self_contact_nodes": ("(f,)", "nodes touching a node not near them at rest"),
    "envelope/peak_stress": ("(m,)", "each triangle's largest surface_stress over the run"),
    "envelope/peak_stress_time": ("(m,)", "when, in a run in time"),
    "envelope/peak_stress_tank_fraction": ("(m,)", "at which tank fraction, in a static "
                                           "sweep"),
    "envelope/peak_strain": ("(m,)", "each triangle's largest principal log strain"),
    "envelope/peak_strain_time, peak_strain_tank_fraction": ("(m,)", "when, or at which "
                                                              "tank fraction"),
    "envelope/polar_deg, azimuth_deg": ("(m,)", "each triangle's place on the rest shape"),
    "events/time, tank_fraction": ("(e,)", "the frame where a topology change is first "
                                   "seen (its time in a run in time, else its tank fraction)"),
    "events/event": ("(e,)", "what changed: fold forms / vanishes, wall contact, self-contact "
                     "or inversion starts / ends"),
    "events/polar_deg, azimuth_deg": ("(e,)", "where a fold is (NaN for the others)"),
    "events/area": ("(e,)", "the fold's rest area, the contact area, the inverted area"),
    "cycles/triangle": ("(c,)", "which of the most loaded triangles"),
    "cycles/stress_range, mean_stress": ("(c,)", "its rainflow cycles"),
    "cycles/count": ("(c,)", "1, or 0.5 for a half cycle"),
}
"""The datasets :func:`annotate` writes -> (shape, meaning); f frames, m triangles (two per
quad of ``/membrane/face_nodes``, :func:`structure.grid.triangles_from_quads`), e events,
c cycles."""

ATTRIBUTES = {
    "stress_law": "what the stresses are from: the incompressible neo-Hookean law of the "
                  "scene's E for rubber (nu >= 0.49) under every model, else the run's law",
    "stress_invalid_frames": "the frames whose stress fields were not finite (written as "
                             "missing); absent when there are none",
    "peak_stress": "the run's largest surface stress over the free sheet (the triangles with "
                   "a free node)",
    "peak_stress_time, peak_stress_tank_fraction": "when, or at which tank fraction",
    "peak_stress_triangle, peak_strain_triangle": "which triangle (an index of the frames' "
                                                  "per-triangle datasets)",
    "peak_stress_membrane": "the membrane part of the peak: that triangle's largest principal "
                            "mid-surface stress in that frame (the rest is bending)",
    "peak_stress_polar_deg, peak_stress_azimuth_deg": "where, on the rest shape",
    "peak_strain": "the run's largest principal log strain",
    "peak_strain_time, peak_strain_tank_fraction": "when, or at which tank fraction",
    "peak_strain_polar_deg, peak_strain_azimuth_deg": "where, on the rest shape",
    "stress_margin, strain_margin": "limits.stress (limits.strain) over the run's peak: "
                                    "below 1, the limit is exceeded (with the limit only)",
    "dynamic_amplification": "a slosh run's peak stress over its static start's (the static "
                             "model at the same volume)",
    "miner_damage, miner_damage_triangle": "Miner's damage per run of the scene, largest over "
                                           "the counted triangles, and which (with "
                                           "fatigue.sn_curve only)",
}
"""The attributes :func:`annotate` writes -> meaning."""


def reference_markdown() -> str:
    """The table of :data:`DATASETS` and :data:`ATTRIBUTES` with their units
    (:func:`fsi.io.output.units_of`), for the user guide."""
    from fsi.io.output import units_of

    def unit(name):
        units = [units_of(n.strip()) or "-" for n in name.split("/")[-1].split(",")]
        return ", ".join(dict.fromkeys(units))

    rows = ["| dataset | shape | units | meaning |", "|---|---|---|---|"]
    rows += [f"| `{name}` | {shape} | {unit(name)} | {text} |"
             for name, (shape, text) in DATASETS.items()]
    rows += ["", "| attribute | units | meaning |", "|---|---|---|"]
    rows += [f"| `{name}` | {unit(name)} | {text} |" for name, text in ATTRIBUTES.items()]
    return "\n".join(rows)
