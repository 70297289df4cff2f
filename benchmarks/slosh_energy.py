"""Energy and linearity of the limp (free-surface) slosh: what the scheme keeps and loses.

    python benchmarks/slosh_energy.py [--fills 0.5 0.53] [--cells 16] [--end-time 5.0]
                                      [--viscosity 0.05] [--pulse-scales 1.0 0.1]
                                      [--convection upwind|none] [--surface limp|linear]
                                      [--smoke]

Runs the bundled ``slosh-half`` scene (a 0.5 m/s^2 sin^2 lateral pulse over 0.1 s, then free
decay, 2 ms windows) at each tank fraction V / (4/3 pi R^3) three ways and prints one JSON
object with, per fill:

* ``energy_drift``: inviscid free decay, the total energy E = K + U (the liquid's kinetic
  energy and the surface's gravitational potential energy, as recorded per window), each
  averaged over one period of the first mode, last period against first, five periods apart
  where the run allows; anchor 0 (an inviscid liquid keeps its energy; the goal is within
  1 %). ``zeta_inviscid`` is the first-mode fit's damping of the same run.
* ``viscous_balance``: the same with a viscous liquid (``--viscosity``, default 0.05 Pa s,
  50 times water's: on these grids water's dissipation, zeta ~ 1e-4, is smaller than the
  scheme's own loss, so it could not be told apart): the energy lost over the same periods
  against the integrated viscous dissipation of the discrete operator, ``lost /
  dissipated`` (anchor 1; goal within 5 %), and ``net_of_inviscid``: the same with the
  inviscid run's loss subtracted (the scheme's own loss).
One case per tank fraction and ``--pulse-scales`` entry (times the scene's pulse).

* ``linearity``: half the pulse: the first mode's amplitude ratio (anchor 0.5, goal within
  2 %) and frequency ratio (anchor 1, goal within 0.5 %).

Anchors are the physics' (energy conserved without viscosity; lost as dissipated with it;
a linear response), not another code's. A full run's JSON also goes to
``docs/data/slosh_energy.json`` (:func:`json_name`: ``slosh_energy_linear.json`` with
``--surface linear``, ``slosh_energy_noconvection.json`` with ``--convection none``). ``--smoke``: :data:`SMOKE` (tank fraction 0.5 on 8^3 cells,
20 ms windows, 2.4 s: three periods after the pulse).
"""
from __future__ import annotations

import argparse
import logging

import numpy as np

from _report import SMOKE_HELP, emit
from fsi.setup.build import build
from fsi.procedures import PROCEDURES
from fsi.procedures.coupled import FLUID_CONVECTIONS
from fsi.scene import load_scene

#: dynamic viscosity (Pa s) of the viscous case: 50 times water's
VISCOSITY = 0.05
#: periods between the first and the last averaged period of the energy
PERIODS = 5
#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("anchors", "goals", "cases")
#: --smoke: the options it sets, and the window (s; the scene's is 2 ms)
SMOKE = dict(fills=[0.5], cells=8, end_time=2.4)
SMOKE_WINDOW = 0.02


def run(fill: float, cells: int, end_time: float, viscosity: float = 0.0,
        pulse_scale: float = 1.0, convection: str = "upwind", surface: str = "limp",
        window: float | None = None):
    """The bundled ``slosh-half`` at tank fraction ``fill`` on ``cells``^3 with
    ``fluid.convection`` and ``slosh.surface`` (and ``slosh.window``, s, unless None): its
    result."""
    scene = load_scene("slosh-half")
    scene.values["slosh"].update(fill=fill, end_time=end_time, surface=surface)
    if window is not None:
        scene.values["slosh"]["window"] = window
    scene.values["fluid"].update(cells=cells, viscosity=viscosity, convection=convection)
    motion = scene.values["motion"]
    motion["amplitude"] = [pulse_scale * a for a in motion["amplitude"]]
    return PROCEDURES["slosh"](build(scene), lambda fraction, message: None)


def period_means(time: np.ndarray, values: np.ndarray, start: float, period: float,
                 count: int) -> np.ndarray:
    """(count,) the means of ``values`` over consecutive periods from ``start`` (s)."""
    out = []
    for k in range(count):
        inside = (time >= start + k * period) & (time < start + (k + 1) * period)
        out.append(float(np.mean(values[inside])))
    return np.asarray(out)


def energy_figures(inviscid, viscous) -> dict:
    """Drift of the inviscid run's energy and the viscous run's energy balance."""
    a = inviscid.attrs
    period = 2 * np.pi / a["omega"]
    w = inviscid.groups["windows"]
    time = w["time"]
    start = a["analysis_start"]
    count = min(PERIODS + 1, int((time[-1] - start) / period))
    if count < 2:
        return dict(energy_failure="the run is shorter than two periods after the pulse")
    energy = w["liquid_kinetic_energy"] + w["potential_energy"]
    means = period_means(time, energy, start, period, count)
    out = dict(periods_apart=count - 1, energy_first=means[0], energy_last=means[-1],
               energy_drift=means[-1] / means[0] - 1, zeta_inviscid=a["zeta"])
    v = viscous.groups["windows"]
    energy_v = v["liquid_kinetic_energy"] + v["potential_energy"]
    means_v = period_means(v["time"], energy_v, start, period, count)
    dissipated = period_means(v["time"], v["dissipated_energy"], start, period, count)
    lost = means_v[0] - means_v[-1]
    spent = dissipated[-1] - dissipated[0]
    lost_inviscid = means[0] - means[-1]
    out.update(viscous_lost=lost, viscous_dissipated=spent,
               viscous_balance=lost / spent if spent > 0 else None,
               net_of_inviscid=(lost - lost_inviscid) / spent if spent > 0 else None,
               zeta_viscous=viscous.attrs.get("zeta"))
    return out


def _surface_amplitude(result) -> float:
    """m: the largest rise or fall of the surface's nodes from the level after the pulse,
    over the frames."""
    heights = result.groups["frames"]["surface_height"]
    return float(np.max(np.abs(heights[1:] - heights[0])))


def linearity_figures(full, half) -> dict:
    """The first mode's amplitude and frequency under half the pulse, over the full one's."""
    fit_full, fit_half = full.attrs, half.attrs
    return dict(amplitude_ratio=fit_half["centre_of_mass_amplitude"]
                / fit_full["centre_of_mass_amplitude"],
                frequency_ratio=fit_half["omega"] / fit_full["omega"])


def json_name(surface: str, convection: str) -> str:
    """The ``docs/data`` file of a full run: ``slosh_energy`` for the limp surface with the
    default convection, ``slosh_energy_<surface>`` for another surface (its convection is
    ``none``), ``slosh_energy_noconvection`` for the limp surface without convection."""
    if surface != "limp":
        return f"slosh_energy_{surface}"
    return "slosh_energy" if convection == "upwind" else "slosh_energy_noconvection"


def main(argv=None) -> None:
    logging.disable(logging.INFO)
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fills", type=float, nargs="+", default=[0.5, 0.53])
    parser.add_argument("--cells", type=int, default=16)
    parser.add_argument("--end-time", type=float, default=5.0)
    parser.add_argument("--viscosity", type=float, default=VISCOSITY)
    parser.add_argument("--pulse-scales", type=float, nargs="+", default=[1.0],
                        help="times the scene's 0.5 m/s^2 pulse; one case per fill and scale")
    parser.add_argument("--convection", choices=sorted(FLUID_CONVECTIONS), default="upwind",
                        help="fluid.convection of every run")
    parser.add_argument("--surface", choices=("limp", "linear"), default="limp",
                        help="slosh.surface of every run (linear needs --convection none)")
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    if args.smoke:
        vars(args).update(SMOKE)
    cases = []
    keys = dict(convection=args.convection, surface=args.surface,
                window=SMOKE_WINDOW if args.smoke else None)
    for fill, scale in ((f, s) for f in args.fills for s in args.pulse_scales):
        inviscid = run(fill, args.cells, args.end_time, pulse_scale=scale, **keys)
        viscous = run(fill, args.cells, args.end_time, viscosity=args.viscosity,
                      pulse_scale=scale, **keys)
        half = run(fill, args.cells, args.end_time, pulse_scale=0.5 * scale, **keys)
        case = dict(fill=fill, cells=args.cells, viscosity=args.viscosity, pulse_scale=scale,
                    convection=args.convection, surface=args.surface,
                    surface_amplitude=_surface_amplitude(inviscid),
                    lambda1=inviscid.attrs.get("lambda1"),
                    wall_seconds=inviscid.attrs["wall_seconds"])
        case.update(energy_figures(inviscid, viscous))
        case.update(linearity_figures(inviscid, half))
        cases.append(case)
    emit(json_name(args.surface, args.convection), dict(benchmark="slosh_energy", anchors=dict(
        energy_drift=0.0, viscous_balance=1.0, amplitude_ratio=0.5, frequency_ratio=1.0),
        goals=dict(energy_drift=0.01, viscous_balance=0.05, amplitude_ratio=0.02,
                   frequency_ratio=0.005), cases=cases), args.smoke)


if __name__ == "__main__":
    main()
