"""``volume-sweep``: the quasi-static fill sweep, volume-controlled.

For each fill phi of ``sweep.fills`` in order, the membrane's equilibrium holding the liquid
volume V(phi) on ``sweep.scale`` (the tank fraction: V = phi (4/3) pi R^3; the thesis's
full-inversion scale: V = V_empty + phi (V_full - V_empty), :mod:`fsi.setup.fill`; its frames
then carry their ``inversion_fraction`` beside the tank fraction) under the hydrostatic load
p = p_ref + rho b . x, the level p_ref its Lagrange multiplier, by the scene's structure model
(:mod:`fsi.setup.models`); each fill starts from the previous equilibrium (continuation). With
``sweep.drain`` the same fills are then run back down (group ``drain``). A model that follows
the path in volume steps (``minimisation``) records the snaps it crossed (group
``limit_points``: the tank fraction, the levels before and after).
"""
from __future__ import annotations

import logging
import time

import numpy as np

from structure.model import MembraneState
from structure.volume import tank_volume

from fsi.setup.fill import FILL_SCALES, check_first_step, check_reachable, full_inversion
from fsi.setup.limits import check_time_step, courant_time_step_limit
from fsi.lifecycle import Progress, Run, RunResult
from fsi.setup.models import STRUCTURE_MODELS, hydrostatic_load
from fsi.registry import Procedure, register_procedure
from fsi.procedures.static import (RELAXATION, SWEEP, full_inversion_parts, report_sweep,
                                   static_frame)

log = logging.getLogger(__name__)


LEGS = {"frames": "filling", "drain": "draining"}
"""A leg's group -> what the progress and the log call it."""


def volume_sweep(setup, progress: Progress) -> RunResult:
    """Quasi-static sweep over ``sweep.fills`` by continuation, then back down with
    ``sweep.drain``."""
    fills = list(setup.scene["sweep"]["fills"])
    full = full_inversion(setup)
    scale = FILL_SCALES[setup.scene["sweep"]["scale"]](setup, full)
    inversion = full.scale if setup.scene["sweep"]["scale"] == "full-inversion" else None
    check_reachable(full, scale, fills, "sweep.fills")
    legs = [("frames", fills)] + ([("drain", fills[::-1])] if setup.scene["sweep"]["drain"]
                                  else [])
    run = Run(progress, sum(len(f) for _, f in legs))
    groups, attrs = full_inversion_parts(setup, full)
    model = STRUCTURE_MODELS[setup.structure_model]
    data = model.prepare(setup)
    state = MembraneState(setup.model.node_rest_position)
    level, done = 0.0, 0
    for group, leg in legs:
        for fill in leg:
            t0 = time.perf_counter()
            load = hydrostatic_load(setup.liquid, float(scale.volume(fill)), level)
            state, info = model.solve(data, setup, state, load)
            if np.isfinite(info.pressure_level):
                level = info.pressure_level
            seconds = time.perf_counter() - t0
            record = static_frame(setup, state.node_position, info.pressure_level, fill,
                                  seconds, info.steps, info.converged, inversion)
            if not info.converged:
                log.warning("%s, tank fraction %.3f: %s model not converged after %d steps",
                            LEGS[group], record["tank_fraction"], setup.structure_model,
                            info.steps)
            run.record(group, record)
            for point in info.limit_points:
                run.record("limit_points", dict(
                    event=np.bytes_(f"{LEGS[group]}: snap crossed by {point.crossed_by}"),
                    tank_fraction=point.liquid_volume / tank_volume(setup.model.radius),
                    pressure_level_before=point.level_before,
                    pressure_level=point.level_after))
            done += 1
            run.progress(done, f"{LEGS[group]}, tank fraction {record['tank_fraction']:.3f}")
    return run.result(groups, **attrs, structure_model=setup.structure_model,
                      fill_scale=setup.scene["sweep"]["scale"])


def _check_setup(setup) -> None:
    check_time_step("relaxation.dt", setup.relaxation.dt,
                    courant_time_step_limit(setup.model, setup.liquid, setup.model.radius))
    check_first_step(setup)


PROCEDURE = register_procedure(Procedure(
    name="volume-sweep",
    summary="volume-controlled quasi-static sweep over the fills (and back down)",
    run=volume_sweep,
    tables={"sweep": SWEEP, "relaxation": RELAXATION},
    check_setup=_check_setup,
    report=report_sweep,
))
