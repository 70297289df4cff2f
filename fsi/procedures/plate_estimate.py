"""``plate-estimate``: the analytical rung of the model ladder (thesis Ch. 3).

A flat diaphragm clamped at the tank's equator, radius a = R, carries the liquid of a tank
fraction phi = V / (4/3 pi R^3) <= 0.5 lying on it (the thesis's Sec. 3.1 case: the body force
turned toward the diaphragm, the liquid's weight pressing it into the gas).  The uniform load q
(``plate.load``):

    hydrostatic:  q = rho g h,  h the liquid depth over the disc, pi (R^2 h - h^3 / 3) = V
                  (the pressure at the disc depends only on the depth; the wall above it
                  carries the rest of the weight);
    weight:       q = rho g V / (pi R^2) = (4/3) phi rho g R (all the weight on the disc, the
                  thesis's "force per unit diaphragm area").

For each fill, the centre deflection w0 and the profile w(r) by every closed form of
:mod:`structure.plate` (linear plate, large-deflection plate, Hencky membrane), each marked
valid or not by its w0 / t range; and the trend of w0 / a with the tank radius (thesis
Fig. 3.4) over ``plate.radius_sweep``.  Microseconds: it tells in advance whether a scene's
diaphragm stays in a range where a closed form holds (it does not, for the thesis's tank).
"""
from __future__ import annotations

import math

import numpy as np

from structure.plate import ESTIMATES, FlatDiaphragm

from fsi.lifecycle import Progress, Run, RunResult
from fsi.registry import Key, Procedure, Table, one_of, register_procedure
from fsi.text import format_table

RADIAL_SAMPLES = 41
"""Radii at which each profile is recorded, 0..a (-)."""
RADIUS_SWEEP_SAMPLES = 61
"""Tank radii of the Fig. 3.4 trend, log-spaced over ``plate.radius_sweep`` (-)."""


def hydrostatic_load(fill: float, radius: float, density: float, gravity: float) -> float:
    """q = rho g h (Pa), h (m) the depth over the equator disc holding V = fill (4/3) pi R^3:
    h / R - (h / R)^3 / 3 = 4 fill / 3, whose root in [0, 1] is h / R = 2 sin(asin(2 fill) / 3)
    (the cubic's trigonometric solution)."""
    return density * gravity * radius * 2.0 * math.sin(math.asin(2.0 * fill) / 3.0)


def weight_load(fill: float, radius: float, density: float, gravity: float) -> float:
    """q = rho g V / (pi R^2) (Pa): the liquid's whole weight over the disc's area."""
    return density * gravity * fill * 4.0 / 3.0 * radius


PLATE_LOADS = {"hydrostatic": hydrostatic_load, "weight": weight_load}


def _fills(v) -> bool:
    return isinstance(v, list) and len(v) >= 1 and all(
        isinstance(c, (int, float)) and not isinstance(c, bool) and 0.0 < c <= 0.5 for c in v)


def _radius_range(v) -> bool:
    return (isinstance(v, list) and len(v) == 2
            and all(isinstance(c, (int, float)) and not isinstance(c, bool) for c in v)
            and 0 < v[0] < v[1] <= 100)


PLATE = Table({
    "fills": Key(list, [0.25, 0.5], _fills, "non-empty list of numbers in (0, 0.5]",
                 "tank fractions V / (4/3 pi R^3) of the liquid lying on the flat equator "
                 "diaphragm"),
    "load": Key(str, "hydrostatic", *one_of(PLATE_LOADS),
                "hydrostatic: q = rho g (depth over the disc); weight: the liquid's weight "
                "over the disc area"),
    "radius_sweep": Key(list, [0.01, 1.0], _radius_range, "[min, max], 0 < min < max <= 100 m",
                        "tank radii of the centre-deflection trend (thesis Fig. 3.4) (m)"),
})
"""[plate]: the fills and load of the flat-diaphragm estimates."""


def _plate(setup, radius: float) -> FlatDiaphragm:
    m = setup.model.material
    return FlatDiaphragm(radius, m.thickness, m.youngs_modulus, m.poisson_ratio)


def _fill_record(setup, plate: FlatDiaphragm, fill: float, load) -> dict:
    gravity = float(np.linalg.norm(setup.liquid.body_acceleration))
    q = load(fill, plate.radius, setup.liquid.density, gravity)
    r = np.linspace(0.0, plate.radius, RADIAL_SAMPLES)
    record = dict(tank_fraction=fill, pressure=q, radial_position=r)
    for name, estimate in ESTIMATES.items():
        record[f"deflection_{name}"] = estimate.profile(plate, q, r)
        record[f"centre_deflection_{name}"] = estimate.centre(plate, q)
        record[f"valid_{name}"] = estimate.valid(plate, q)
    return record


def plate_estimate(setup, progress: Progress) -> RunResult:
    """The closed forms at each fill of ``plate.fills``, then the radius trend."""
    table = setup.scene["plate"]
    load = PLATE_LOADS[table["load"]]
    fills = list(table["fills"])
    run = Run(progress, len(fills) + 1)
    plate = _plate(setup, setup.model.radius)
    for k, fill in enumerate(fills):
        run.record("plate", _fill_record(setup, plate, fill, load))
        run.progress(k + 1, f"tank fraction {fill:.2f}")
    for radius in np.geomspace(*table["radius_sweep"], RADIUS_SWEEP_SAMPLES):
        record = {f"fill_{100 * f:05.1f}": _fill_record(setup, _plate(setup, radius), f, load)
                  for f in fills}
        run.record("radius_sweep", _radius_record(radius, record))
    run.progress(len(fills) + 1, "radius trend")
    return run.result(load=table["load"], flat_radius=plate.radius,
                      thickness=plate.thickness,
                      **{f"valid_range_{n}": np.asarray(e.valid_range, dtype=float)
                         for n, e in ESTIMATES.items()})


def _radius_record(radius: float, by_fill: dict) -> dict:
    """One tank radius of the trend: radius (m), and per estimate the centre deflection (m)
    at each fill, (n_fills,)."""
    out = {"tank_radius": radius}
    for name in ESTIMATES:
        out[f"centre_deflection_{name}"] = np.array(
            [rec[f"centre_deflection_{name}"] for rec in by_fill.values()])
        out[f"valid_{name}"] = np.array([rec[f"valid_{name}"] for rec in by_fill.values()])
    return out


PLATE_COLUMNS = [("tank fraction", "-"), ("load", "Pa"), ("estimate", ""), ("w0", "mm"),
                 ("w0/t", "-"), ("valid w0/t", ""), ("in range", "")]
"""The columns of the report's table: per fill and estimate, the centre deflection w0, its
ratio to the thickness t, the estimate's validity range and whether w0/t is in it."""
PLATE_FORMATS = [".3f", ".1f", "", ".2f", ".1f", "", ""]


def report_plate(result: RunResult) -> None:
    """Centre deflection by fill and estimate, with w0 / t and validity (a table)."""
    a = result.attrs
    print(f"flat diaphragm, radius {a['flat_radius']:.4f} m, thickness {1e3 * a['thickness']:.3f}"
          f" mm, {a['load']} load")
    print(format_table(PLATE_COLUMNS, plate_rows(result), PLATE_FORMATS))


def plate_rows(result: RunResult) -> list[tuple]:
    """The rows of the report's table (:data:`PLATE_COLUMNS`), one per fill and estimate; the
    fill and load on the first of each fill's rows only."""
    g, a = result.groups["plate"], result.attrs
    rows = []
    for k, fill in enumerate(g["tank_fraction"]):
        for j, name in enumerate(ESTIMATES):
            w0 = float(g[f"centre_deflection_{name}"][k])
            lo, hi = (float(v) for v in a[f"valid_range_{name}"])
            rows.append((float(fill) if j == 0 else None,
                         float(g["pressure"][k]) if j == 0 else None, name, 1e3 * w0,
                         w0 / a["thickness"], f"{lo:g}..{hi:g}",
                         "yes" if g[f"valid_{name}"][k] else "no"))
    return rows


PROCEDURE = register_procedure(Procedure(
    name="plate-estimate",
    summary="closed forms of a flat clamped diaphragm under the liquid (thesis Ch. 3): "
            "linear plate, large-deflection plate, Hencky membrane, each with its validity",
    run=plate_estimate,
    tables={"plate": PLATE},
    report=report_plate,
))
