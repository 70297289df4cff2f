"""Procedures a scene can run, in a registry: ``volume-sweep``, ``thesis-ramp`` and
``coupled-fill`` (:mod:`fsi.coupled`).

A procedure takes a :class:`fsi.build.Setup` and a progress callback and returns a
:class:`RunResult`: named groups of frames (arrays with a leading frame axis) that
:mod:`fsi.output` writes as HDF5 groups. Procedures never write files or plot.
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from structure.model import MembraneState
from structure.statics import strain_error
from structure.thesis import ThesisState, step
from structure.volume import FillScale, liquid_volume

from .build import Setup
from .fill import FullInversion, full_inversion
from .models import STRUCTURE_MODELS

log = logging.getLogger(__name__)

Progress = Callable[[float, str], None]
"""progress(fraction_done in [0, 1], message)."""

PROCEDURES: dict[str, Callable] = {}


def register_procedure(name: str):
    """Decorator: register a procedure under ``name`` (the scene's ``scene.procedure``)."""
    def deco(func):
        PROCEDURES[name] = func
        return func
    return deco


@dataclass
class RunResult:
    """groups: {group name: {dataset name: array with leading frame axis}}; attrs: run facts."""

    groups: dict = field(default_factory=dict)
    attrs: dict = field(default_factory=dict)


def _frame_record(setup: Setup, scale: FillScale, pos, level, target_fill, seconds, steps,
                  converged):
    volume = liquid_volume(setup.model, pos)
    mean, worst = strain_error(setup.model, pos)
    tank = 4.0 / 3.0 * np.pi * setup.model.radius**3
    return dict(node_position=pos.copy(), fill_fraction=float(scale.fill(volume)),
                target_fill_fraction=float(target_fill), liquid_volume=volume,
                tank_fraction=volume / tank,
                pressure_reference=float(level),
                pressure_level=setup.liquid.equivalent_height(level),
                wall_seconds=seconds, relaxation_steps=steps, converged=bool(converged),
                strain_error=mean, strain_max=worst)


def _stack(records: list[dict]) -> dict:
    return {k: np.asarray([r[k] for r in records]) for k in records[0]}


def _new_result(setup: Setup, full: FullInversion) -> RunResult:
    """RunResult carrying the fill scale and the 100 % reference shape."""
    return RunResult(
        groups=dict(full_inversion=dict(node_position=full.state.node_position[None],
                                        liquid_volume=np.array([full.info.liquid_volume]),
                                        strain_error=np.array([full.info.strain_error]),
                                        strain_max=np.array([full.info.strain_max]),
                                        converged=np.array([full.info.converged]))),
        attrs=dict(empty_volume=full.scale.empty_volume, full_volume=full.scale.full_volume,
                   mirrored_volume=full.mirrored_volume,
                   full_pressure_reference=full.info.pressure_level,
                   full_height=setup.liquid.equivalent_height(full.info.pressure_level)))


@register_procedure("volume-sweep")
def volume_sweep(setup: Setup, progress: Progress) -> RunResult:
    """Quasi-static sweep over ``sweep.fills`` by continuation (each fill starts from the
    previous equilibrium); with ``sweep.drain`` the same fills are then run back down."""
    fills = list(setup.scene["sweep"]["fills"])
    full = full_inversion(setup)
    scale = full.scale
    legs = [("frames", fills)]
    if setup.scene["sweep"]["drain"]:
        legs.append(("drain", fills[::-1]))
    total = sum(len(f) for _, f in legs)
    done = 0
    state = MembraneState(setup.model.node_rest_position)
    result = _new_result(setup, full)
    result.attrs["structure_model"] = setup.structure_model
    model = STRUCTURE_MODELS[setup.structure_model]
    data = model.prepare(setup)
    level = 0.0
    for group, leg in legs:
        records = []
        for fill in leg:
            t0 = time.perf_counter()
            state, info = model.solve(data, setup, state, float(scale.volume(fill)), level)
            if np.isfinite(info.pressure_level):
                level = info.pressure_level
            seconds = time.perf_counter() - t0
            if not info.converged:
                log.warning("%s fill %.3f: %s model not converged after %d steps", group, fill,
                            setup.structure_model, info.steps)
            records.append(_frame_record(setup, scale, state.node_position, info.pressure_level,
                                         fill, seconds, info.steps, info.converged))
            done += 1
            progress(done / total, f"{group} fill {fill:.2f}")
        result.groups[group] = _stack(records)
    return result


@register_procedure("thesis-ramp")
def thesis_ramp(setup: Setup, progress: Progress) -> RunResult:
    """The thesis's own procedure (App. B): the equivalent height is ramped linearly from
    ``height_start`` R to ``height_end`` R over ``end_time`` with the thesis stepper; frames are
    recorded every ``frame_interval`` steps (group ``history``); then, as App. J does, for each
    fill in ``sweep.fills`` the recorded frame whose volume is nearest fill x (volume of the last
    frame) is picked (group ``frames``). ``frames/fill_fraction`` is the fill on this project's
    scale (see :mod:`structure.volume`); ``frames/target_fill_fraction`` the App. J target."""
    th = setup.scene["thesis"]
    model, liquid = setup.model, setup.liquid
    n_steps = int(round(th["end_time"] / th["dt"]))
    h0, h1 = th["height_start"] * model.radius, th["height_end"] * model.radius
    full = full_inversion(setup)
    scale = full.scale
    state = ThesisState(model.node_rest_position)
    history = []
    t_start = time.perf_counter()
    for k in range(1, n_steps + 1):
        h = h0 + (h1 - h0) * k / n_steps  # App. B updates the height before each step
        level = liquid.reference_pressure(h)
        state = step(model, state, liquid.pressure(state.node_position, level),
                     liquid.body_acceleration, setup.thesis)
        if k % th["frame_interval"] == 0 or k == n_steps:
            rec = _frame_record(setup, scale, state.node_position, level, np.nan,
                                time.perf_counter() - t_start, k, True)
            rec["time"] = k * th["dt"]
            rec["node_speed_max"] = float(np.linalg.norm(state.node_velocity, axis=1).max())
            history.append(rec)
            progress(k / n_steps, f"t = {k * th['dt']:.3f} s, h = {h:+.4f} m")
    hist = _stack(history)
    final_volume = hist["liquid_volume"][-1]
    picked = []
    for fill in setup.scene["sweep"]["fills"]:
        i = int(np.argmin(np.abs(hist["liquid_volume"] - fill * final_volume)))
        rec = {k: v[i] for k, v in hist.items()}
        rec["target_fill_fraction"] = float(fill)
        picked.append(rec)
    result = _new_result(setup, full)
    result.groups.update(frames=_stack(picked), history=hist)
    result.attrs["app_j_full_volume"] = float(final_volume)
    return result


from . import coupled  # noqa: E402,F401  (registers coupled-fill)
