"""A coupled window of the XPBD membrane's energies taken by the implicit generalised-alpha
step (:mod:`structure.newton.dynamics`): one Newton-solved step per window, no Courant limit.

:func:`alpha_window` has the signature of :data:`structure.xpbd.WINDOW_SCHEMES`, so the
coupling's membrane participant runs it as it runs the XPBD schemes. The membrane is the
XPBD model's (the plane-stress blocks, the calibrated bending, the wall as a penalty:
:meth:`structure.newton.system.NewtonModel.from_xpbd`), its load the coupled liquid's node
pressure held over the window (follower form), its volume held at the window's end with the
level as the multiplier. Where a step's Newton iteration does not converge the step is
halved (a snap is passed with the sheet's inertia, which only a step near the snap's own time
scale feels), down to :data:`MAX_HALVINGS` times, and doubled again after each success; the
volume moves linearly across the window. Past the smallest step it raises
:class:`structure.newton.dynamics.NewtonDivergence`.
"""
from __future__ import annotations

import weakref
from dataclasses import replace

from ..load import Load, StepInfo
from ..model import MembraneState
from .dynamics import AlphaSettings, AlphaState, NewtonDivergence, step
from .system import NewtonModel

RHO_INF = 0.0
"""The window's high-frequency spectral radius unless set (``coupling.rho_inf``): 0, every
force at the step's end as the BDF2 liquid has them, and a snapping fold's ringing removed
(the trapezoidal rule, 1, let the coupling diverge at N = 26; docs/notes/newton-statics.md)."""

MAX_HALVINGS = 12
"""A window's step is halved at most this many times (to 1/4096 of the window: 0.5 ms of a
2 s window, the time scale of a fold's snap) before the window fails (-)."""

_MODELS: dict[int, tuple] = {}
"""id(XPBD model) -> (weak reference to it, its :class:`NewtonModel`): the tangent's
pattern is built once per membrane, not once per window."""


def newton_model(model) -> NewtonModel:
    """The :class:`NewtonModel` of an XPBD model (or the model itself when it is one),
    built once per model object and kept while the model lives."""
    if isinstance(model, NewtonModel):
        return model
    key = id(model)
    kept = _MODELS.get(key)
    if kept is not None and kept[0]() is model:
        return kept[1]
    built = NewtonModel.from_xpbd(model, bending=True, load_form="follower")
    _MODELS[key] = (weakref.ref(model, lambda _ref, key=key: _MODELS.pop(key, None)), built)
    return built


def alpha_settings(settings) -> AlphaSettings:
    """``settings`` as they are when they are :class:`AlphaSettings`; from XPBD settings,
    :data:`RHO_INF` and their node damping."""
    if isinstance(settings, AlphaSettings):
        return settings
    return AlphaSettings(rho_inf=RHO_INF,
                         node_damping=float(getattr(settings, "node_damping", 0.0)))


def alpha_window(model, state: MembraneState, load: Load, dt: float, settings,
                 history=None) -> tuple[AlphaState, StepInfo]:
    """The window of ``dt`` (s) from ``state`` under ``load`` by generalised-alpha steps
    (module doc); ``history`` is not used (the method is one-step). Returns the state at the
    window's end and a :class:`structure.load.StepInfo` with the Newton iterations of all
    its steps and the level (Pa)."""
    if not dt > 0:
        raise ValueError(f"window duration must be > 0 s, got {dt!r}")
    return _steps(newton_model(model), state, load, dt, alpha_settings(settings))


def _steps(model: NewtonModel, state, load: Load, dt: float, settings: AlphaSettings):
    """The window by steps that halve where Newton fails and double again after a success
    (never past the window's end, never below dt / 2^MAX_HALVINGS), the volume target moving
    linearly in time across the window."""
    held = load.volume_target is not None
    start_volume = model.liquid_volume(state.node_position) if held else None
    smallest = dt / 2 ** MAX_HALVINGS
    current, iterations, done, size = state, 0, 0.0, dt
    level = load.pressure_level
    while done < dt * (1.0 - 1e-12):
        size = min(size, dt - done)
        part = replace(load, pressure_level=level)
        if held:
            part = replace(part, volume_target=start_volume + (
                load.volume_target - start_volume) * (done + size) / dt)
        try:
            current, info = step(model, current, part, size, settings)
        except NewtonDivergence:
            if size <= smallest * (1.0 + 1e-9):
                raise
            size = max(0.5 * size, smallest)
            continue
        iterations += info.substeps
        level = info.pressure_level
        done += size
        size *= 2.0
    return current, StepInfo(iterations, level)


def settled(model, state: MembraneState, load: Load):
    """The equilibrium of the Newton model of ``model`` under ``load`` (its volume target held)
    from ``state``: a start found by another solver (XPBD's relaxation, whose bias leaves
    residual forces under these energies) put at rest for :func:`alpha_window`, so that the
    first window does not start with a jolt. Returns (:class:`MembraneState`,
    :class:`structure.load.Equilibrium`); not converged is the Equilibrium's to say."""
    from .statics import solve_equilibrium

    settled_state, equilibrium, _ = solve_equilibrium(
        newton_model(model), MembraneState(state.node_position.copy()), load)
    return settled_state, equilibrium
