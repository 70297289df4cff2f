"""What the two static procedures (``volume-sweep``, ``thesis-ramp``) share: the ``[sweep]``
and ``[relaxation]`` tables, the frame record of a static equilibrium, the 100 % reference
that every static result carries, and the summary ``fsi run`` prints."""
from __future__ import annotations

import numpy as np

from structure.statics import strain_error
from structure.volume import FillScale

from fsi.setup.fill import FILL_SCALES, FullInversion
from fsi.lifecycle import membrane_frame
from fsi.registry import Key, Table, one_of, positive


def _fills(v):
    return isinstance(v, list) and len(v) >= 1 and all(
        isinstance(c, (int, float)) and not isinstance(c, bool) and 0.0 <= c <= 1.0 for c in v)


SWEEP = Table({
    "fills": Key(list, [round(0.1 * k, 10) for k in range(1, 8)], _fills,
                 "non-empty list of numbers in [0, 1]",
                 "fills on the sweep.scale, in order (tank: from the rest shape's, 0.003, to "
                 "the fully inverted membrane's, 0.79, at N = 26 clamped)"),
    "scale": Key(str, "tank", *one_of(FILL_SCALES),
                 "scale of sweep.fills: tank (V / (4/3 pi R^3)) or full-inversion (the "
                 "thesis's App. J: 0 rest shape, 1 the fully inverted equilibrium) "
                 "(volume-sweep; thesis-ramp picks frames on App. J's last-frame scale)"),
    "drain": Key(bool, True, lambda v: True, "true or false",
                 "after filling, sweep back down the same fills (volume-sweep)"),
    "full_height": Key(float, 1.05, lambda v: 0 < v <= 100, "0 < value <= 100 (x radius)",
                       "equivalent height / radius of the load whose fully inverted "
                       "equilibrium is 100 % fill (App. J: the ramp's final +1.05)"),
})
"""[sweep]: the fills of a static result and the load of its 100 % reference."""

RELAXATION = Table({
    "dt": Key(float, None, positive, "> 0 s, below the explicit stability limit",
              "pseudo time step (s); default: the solver's"),
    "damping": Key(float, None, lambda v: 0 <= v < 1, "0 <= value < 1",
                   "velocity fraction removed per pseudo-step; default: the solver's"),
    "tolerance": Key(float, None, lambda v: 0 < v < 1, "0 < value < 1",
                     "converged when max node move per step / node size < tolerance"),
    "max_steps": Key(int, None, lambda v: v >= 1, ">= 1", "pseudo-steps per fill at most"),
})
"""[relaxation]: the thesis model's static relaxation (:mod:`structure.statics`)."""


def static_frame(setup, scale: FillScale, node_position, pressure_level, target_fill,
                 seconds, steps, converged) -> dict:
    """A static equilibrium's frame: :func:`fsi.lifecycle.membrane_frame`, the target fill,
    wall seconds, solver steps, convergence and the thesis strain measures."""
    mean, worst = strain_error(setup.model, node_position)
    return dict(membrane_frame(setup, scale, node_position, pressure_level),
                target_fill_fraction=float(target_fill), wall_seconds=seconds,
                relaxation_steps=steps, converged=bool(converged), strain_error=mean,
                strain_max=worst)


def full_inversion_parts(setup, full: FullInversion) -> tuple[dict, dict]:
    """(groups, attrs) carrying the fill scale and the 100 % reference shape."""
    info = full.info
    groups = dict(full_inversion=dict(node_position=full.state.node_position[None],
                                      liquid_volume=np.array([info.liquid_volume]),
                                      strain_error=np.array([info.strain_error]),
                                      strain_max=np.array([info.strain_max]),
                                      converged=np.array([info.converged])))
    attrs = dict(empty_volume=full.scale.empty_volume, full_volume=full.scale.full_volume,
                 mirrored_volume=full.mirrored_volume, full_pressure_level=info.pressure_level,
                 full_height=setup.liquid.equivalent_height(info.pressure_level))
    return groups, attrs


def report_sweep(result) -> None:
    """The fill table ``fsi run`` prints after a static procedure."""
    a = result.attrs
    print(f"100 % fill = fully inverted equilibrium at h = {a['full_height']:.4f} m: "
          f"{a['full_volume']:.6e} m^3 = {a['full_volume'] / a['mirrored_volume']:.4f} of the "
          f"mirrored rest shape")
    for name in ("frames", "drain"):
        if name not in result.groups:
            continue
        g = result.groups[name]
        print(f"[{name}]  target   fill    tank    volume(m^3)   h(m)     strain  max-strain  "
              f"steps  s   (fill on the {a.get('fill_scale', 'full-inversion')} scale; tank: "
              f"V / (4/3 pi R^3))")
        for k in range(len(g["fill_fraction"])):
            print(f"  {g['target_fill_fraction'][k]:8.3f} {g['fill_fraction'][k]:7.4f} "
                  f"{g['tank_fraction'][k]:7.4f} "
                  f"{g['liquid_volume'][k]:12.6e} {g['equivalent_height'][k]:8.4f} "
                  f"{g['strain_error'][k]:8.5f} {g['strain_max'][k]:8.5f} "
                  f"{int(g['relaxation_steps'][k]):6d} {g['wall_seconds'][k]:6.2f}")
