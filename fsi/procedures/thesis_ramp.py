"""``thesis-ramp``: the thesis's own procedure (Levine 2014, App. B and App. J).

The equivalent fluid height h is ramped linearly from ``height_start`` R to ``height_end`` R
over ``end_time``, updated before each step, and the thesis stepper
(:func:`structure.thesis.step`) advances the membrane under p = rho |b| h + rho b . x at
``thesis.dt``; frames are recorded every ``frame_interval`` steps (group ``history``). Then, as
App. J does, for each fill in ``sweep.fills`` the recorded frame whose volume is nearest
fill x (volume of the last frame) is picked (group ``frames``). Every frame carries its tank
fraction and, beside it, ``inversion_fraction``, the fill on this project's full-inversion
scale (:mod:`fsi.setup.fill`); ``frames/target_fill`` is the App. J target (on the ramp's
last-frame scale).
"""
from __future__ import annotations

import numpy as np

from structure.thesis import DAMPING_MODES, ThesisSettings, ThesisState, step

from fsi.io.checkpoint import CheckpointDue, write as write_checkpoint
from fsi.setup.fill import check_first_step, full_inversion
from fsi.setup.limits import check_time_step, courant_time_step_limit
from fsi.lifecycle import Progress, Run, RunResult, stack
from fsi.setup.models import hydrostatic_load
from fsi.registry import (Key, Procedure, SceneError, Table, one_of, positive,
                          register_procedure, short_number)
from fsi.procedures.static import (RELAXATION, SWEEP, full_inversion_parts, report_sweep,
                                   static_frame)

MAX_STEPS = 5e7
"""Steps of one ramp at most (end_time / dt)."""

def _check_thesis(th: dict) -> None:
    steps = th["end_time"] / th["dt"]
    if steps > MAX_STEPS:
        raise SceneError(f"scene key 'thesis.dt' = {th['dt']!r}: end_time/dt = {steps:.3g} steps; "
                         f"allowed at most {short_number(MAX_STEPS)}")


THESIS = Table({
    "dt": Key(float, 1e-4, positive, "> 0 s, below the explicit stability limit",
              "time step (s) (thesis dt)"),
    "end_time": Key(float, 5.0, positive, "> 0 s", "ramp duration (s) (thesis endtime)"),
    "height_start": Key(float, -1.05, lambda v: -10 <= v <= 10, "-10..10 (x radius)",
                        "initial equivalent height / radius (thesis -1.05)"),
    "height_end": Key(float, 1.05, lambda v: -10 <= v <= 10, "-10..10 (x radius)",
                      "final equivalent height / radius (thesis +1.05)"),
    "steady_state": Key(bool, True, lambda v: True, "true or false",
                        "reset acceleration each step (thesis SteadyState)"),
    "damping": Key(str, "courant-drag", *one_of(DAMPING_MODES),
                   "damping mode (docs/user-guide/scenes.md, 'Thesis damping modes')"),
    "frame_interval": Key(int, 100, lambda v: v >= 1, ">= 1",
                          "steps between recorded frames (thesis 0.05 s / dt)"),
    "checkpoint_interval": Key(int, 0, lambda v: v >= 0, ">= 0",
                               "steps between checkpoints (fsi run --resume continues from "
                               "the last); 0: none by count"),
    "checkpoint_seconds": Key(float, 0.0, lambda v: v >= 0, ">= 0 s",
                              "wall seconds between checkpoints; 0: none by time"),
}, _check_thesis)
"""[thesis]: the ramp and the thesis stepper's settings (App. B names in brackets)."""


def thesis_settings(setup) -> ThesisSettings:
    """The thesis stepper's settings from ``[thesis]`` and the scene's constraints."""
    th = setup.scene["thesis"]
    return ThesisSettings(steady_state=th["steady_state"], damping=th["damping"],
                          constraints=setup.constraints)


def thesis_ramp(setup, progress: Progress) -> RunResult:
    """Ramp the equivalent height with the thesis stepper, then pick frames by volume."""
    th = setup.scene["thesis"]
    model, liquid, settings = setup.model, setup.liquid, thesis_settings(setup)
    n_steps = int(round(th["end_time"] / th["dt"]))
    h0, h1 = th["height_start"] * model.radius, th["height_end"] * model.radius
    full = full_inversion(setup)
    run = Run(progress, n_steps, th["frame_interval"])
    state, first = ThesisState(model.node_rest_position), 1
    if setup.resume is not None:
        state, first = setup.resume["state"], setup.resume["next_step"]
        run.resumed(setup.resume)
    due = CheckpointDue(th["checkpoint_interval"], th["checkpoint_seconds"])
    for k in range(first, n_steps + 1):
        h = h0 + (h1 - h0) * k / n_steps  # App. B updates the height before each step
        level = liquid.reference_pressure(h)
        state, _ = step(model, state, hydrostatic_load(liquid, pressure_level=level), th["dt"],
                        settings)
        if run.frame_due(k):
            run.record("history", dict(
                static_frame(setup, state.node_position, level, np.nan, run.elapsed(), k,
                             True, full.scale),
                time=k * th["dt"],
                node_speed_max=float(np.linalg.norm(state.node_velocity, axis=1).max())))
            run.progress(k, f"t = {k * th['dt']:.3f} s, h = {h:+.4f} m")
        if setup.checkpoint is not None and k < n_steps and due(k):
            write_checkpoint(setup.checkpoint, dict(state=state, next_step=k + 1,
                                                    groups=run.groups, elapsed=run.elapsed(),
                                                    scene=setup.scene.text))
    history = stack(run.groups["history"])
    groups, attrs = full_inversion_parts(setup, full)
    groups["frames"] = pick_by_volume(history, setup.scene["sweep"]["fills"])
    return run.result(groups, **attrs, app_j_full_volume=float(history["liquid_volume"][-1]),
                      fill_scale="full-inversion")


def pick_by_volume(history: dict, fills) -> dict:
    """App. J: for each fill, the frame of ``history`` whose liquid volume is nearest
    fill x (the last frame's volume), with ``target_fill`` = fill."""
    final_volume = history["liquid_volume"][-1]
    picked = []
    for fill in fills:
        i = int(np.argmin(np.abs(history["liquid_volume"] - fill * final_volume)))
        picked.append(dict({k: v[i] for k, v in history.items()},
                           target_fill=float(fill)))
    return stack(picked)


def _check_setup(setup) -> None:
    th = setup.scene["thesis"]
    h = max(abs(th["height_start"]), abs(th["height_end"])) * setup.model.radius
    check_time_step("thesis.dt", th["dt"], courant_time_step_limit(setup.model, setup.liquid, h))
    check_first_step(setup)  # the fill scale's full inversion


PROCEDURE = register_procedure(Procedure(
    name="thesis-ramp",
    summary="the thesis's equivalent-height ramp with its stepper, frames picked by volume",
    run=thesis_ramp,
    tables={"thesis": THESIS, "sweep": SWEEP, "relaxation": RELAXATION},
    structure_model="thesis",
    check_setup=_check_setup,
    report=report_sweep,
))
