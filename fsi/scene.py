"""Scene files (TOML): schema, defaults and validation.

A scene is a TOML file with the sections below. Every key has a type, a default and an allowed
range; unknown keys, wrong types and out-of-range values raise :class:`SceneError` naming the
key, the value and what is allowed, before anything is computed or written. The schema is the
single place where defaults live; README's scene reference is generated from the same table
(``fsi scenes --reference``).
"""
from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any, Callable

from coupling import ACCELERATIONS, SCHEMES
from coupling.scheme import EXTRAPOLATION_WEIGHTS, ON_MAX_ITERATIONS

from . import constants
from .motion import MOTIONS

PROCEDURE_NAMES = ("volume-sweep", "thesis-ramp", "coupled-fill")


class SceneError(ValueError):
    """A scene file is malformed: the message names the key, the value and the allowed range."""


@dataclass(frozen=True)
class Key:
    """One scene key: Python type, default, check (value -> bool), allowed range text, doc."""

    kind: type
    default: Any
    check: Callable[[Any], bool]
    allowed: str
    doc: str


def _pos(v):
    return v > 0


def _vec3(v):
    return isinstance(v, list) and len(v) == 3 and all(
        isinstance(c, (int, float)) and not isinstance(c, bool) and math.isfinite(c) for c in v)


def _history(v):
    """Rows [t, ax, ay, az] of finite numbers, times strictly increasing."""
    if not isinstance(v, list) or not all(isinstance(r, list) and len(r) == 4 and _vec3(r[1:])
                                          and _vec3(r[:3]) for r in v):
        return False
    times = [r[0] for r in v]
    return all(b > a for a, b in zip(times, times[1:]))


def _fills(v):
    return isinstance(v, list) and len(v) >= 1 and all(
        isinstance(c, (int, float)) and not isinstance(c, bool) and 0.0 <= c <= 1.0 for c in v)


SCHEMA: dict[str, dict[str, Key]] = {
    "scene": {
        "name": Key(str, "unnamed", lambda v: len(v) > 0, "non-empty text", "scene name"),
        "description": Key(str, "", lambda v: True, "any text", "one-line description"),
        "procedure": Key(str, "volume-sweep", lambda v: v in PROCEDURE_NAMES,
                         "'volume-sweep', 'thesis-ramp' or 'coupled-fill'",
                         "volume-controlled quasi-static sweep, the thesis's height ramp, or "
                         "the dynamic fill through the port coupled to the liquid's flow"),
    },
    "tank": {
        "radius": Key(float, constants.TANK_RADIUS, _pos, "> 0 m", "spherical tank radius (m)"),
    },
    "membrane": {
        "grid_size": Key(int, 26, lambda v: v >= 4 and v % 2 == 0, "even integer >= 4",
                         "nodes per grid side (thesis GridSize)"),
        "thickness": Key(float, constants.MEMBRANE_THICKNESS, _pos, "> 0 m",
                         "membrane thickness (m)"),
        "density": Key(float, constants.MEMBRANE_DENSITY, _pos, "> 0 kg/m^3",
                       "membrane density (kg/m^3)"),
        "youngs_modulus": Key(float, constants.MEMBRANE_YOUNGS_MODULUS, _pos, "> 0 Pa",
                              "Young's modulus (Pa)"),
        "poisson_ratio": Key(float, 0.5, lambda v: 0 <= v <= 0.5, "0..0.5",
                             "Poisson ratio (xpbd and shell models; rubber 0.5)"),
        "support": Key(str, "clamped", lambda v: v in ("clamped", "simply-supported"),
                       "'clamped' or 'simply-supported'",
                       "rim support: two fixed rings (clamped) or one (simply supported)"),
    },
    "structure": {
        "model": Key(str, "auto", lambda v: v in ("auto", "thesis", "xpbd", "shell"),
                     "'auto', 'thesis', 'xpbd' or 'shell'",
                     "membrane model of a volume sweep (README, 'Choosing a structure model'); "
                     "auto: the cheapest meeting structure.accuracy; coupled-fill runs xpbd"),
        "accuracy": Key(float, 5.0, lambda v: 0 < v <= 100, "0 < value <= 100 (%)",
                        "Eqn 6.1 error the scene accepts, for model = 'auto' (%)"),
        "shell_law": Key(str, "saint-venant-kirchhoff",
                         lambda v: v in ("saint-venant-kirchhoff", "neo-hookean"),
                         "'saint-venant-kirchhoff' or 'neo-hookean'",
                         "membrane law of the shell model"),
    },
    "liquid": {
        "density": Key(float, constants.WATER_DENSITY, _pos, "> 0 kg/m^3",
                       "liquid density (kg/m^3)"),
        "body_acceleration": Key(list, [0.0, 0.0, -constants.STANDARD_GRAVITY], _vec3,
                                 "three finite numbers (m/s^2)",
                                 "gravity minus tank acceleration, tank frame (m/s^2)"),
    },
    "constraints": {
        "error_limit": Key(float, 1.0, lambda v: 0 < v < 100, "0 < value < 100 (%)",
                           "in-plane strain limit (thesis ErrorLimit, %)"),
        "bend_limit_iterations": Key(int, 10, lambda v: 0 <= v <= 1000, "0..1000",
                                     "bend-limiting passes per step (thesis BendDamping); thesis-ramp only, "
                                     "the static sweep runs without (README)"),
        "self_collision": Key(bool, False, lambda v: True, "true or false",
                              "self-collision (thesis CollisionDetection), both procedures "
                              "(the sweep is ~8x slower with it, README)"),
        "collision_buffer": Key(float, 1.0, lambda v: 0 < v <= 1, "0 < value <= 1",
                                "collision distance / shortest rest edge (thesis Cbuffer)"),
        "constraint_iterations": Key(int, 1, lambda v: 1 <= v <= 100, "1..100",
                                     "constraint rounds per step (thesis ConstraintIterations); "
                                     "thesis-ramp only"),
    },
    "sweep": {
        "fills": Key(list, [round(0.1 * k, 10) for k in range(11)], _fills,
                     "non-empty list of numbers in [0, 1]", "fill fractions, in order"),
        "drain": Key(bool, True, lambda v: True, "true or false",
                     "after filling, sweep back down the same fills"),
        "full_height": Key(float, 1.05, lambda v: 0 < v <= 100, "0 < value <= 100 (x radius)",
                           "equivalent height / radius of the load whose fully inverted "
                           "equilibrium is 100 % fill (App. J: the ramp's final +1.05)"),
    },
    "relaxation": {
        "dt": Key(float, None, _pos, "> 0 s, below the explicit stability limit",
                  "pseudo time step (s); default: the solver's"),
        "damping": Key(float, None, lambda v: 0 <= v < 1, "0 <= value < 1",
                       "velocity fraction removed per pseudo-step; default: the solver's"),
        "tolerance": Key(float, None, lambda v: 0 < v < 1, "0 < value < 1",
                         "converged when max node move per step / node size < tolerance"),
        "max_steps": Key(int, None, lambda v: v >= 1, ">= 1", "pseudo-steps per fill at most"),
    },
    "dynamics": {
        "start_fill": Key(float, 0.5, lambda v: 0 < v < 1, "0 < value < 1",
                          "coupled-fill: fill at t = 0, on the mirrored scale (liquid volume "
                          "over the mirrored hemisphere's), static equilibrium"),
        "window": Key(float, 2e-3, lambda v: 0 < v <= 1, "0 < value <= 1 s",
                      "coupled-fill: coupling time window (s)"),
        "end_time": Key(float, 0.2, _pos, "> 0 s", "coupled-fill: simulated time (s)"),
        "frame_interval": Key(int, 5, lambda v: v >= 1, ">= 1",
                              "coupled-fill: windows between recorded frames"),
        "substep_fraction": Key(float, 0.3, lambda v: 0 < v <= 1, "0 < value <= 1",
                                "coupled-fill: XPBD substep / explicit limit of the load "
                                "(0.3: about 1 % stiffness bias, README)"),
    },
    "motion": {
        "kind": Key(str, "none", lambda v: v in MOTIONS,
                    ", ".join(repr(k) for k in sorted(MOTIONS)),
                    "coupled-fill: tank acceleration a(t); the liquid feels "
                    "liquid.body_acceleration - a(t) (README, 'Tank motion')"),
        "amplitude": Key(list, [0.0, 0.0, 0.0], _vec3, "three finite numbers (m/s^2)",
                         "sine: a = amplitude sin(2 pi frequency t) (m/s^2)"),
        "frequency": Key(float, 1.0, lambda v: v >= 0, ">= 0 Hz", "sine: frequency (Hz)"),
        "history": Key(list, [], _history,
                       "rows [t, ax, ay, az], times increasing (s, m/s^2)",
                       "table: a(t) piecewise linear through the rows, held outside them"),
    },
    "port": {
        "flow": Key(float, 5e-4, lambda v: abs(v) <= 1.0, "-1..1 m^3/s",
                    "coupled-fill: volume flow into the liquid through the bottom port "
                    "(m^3/s; negative drains)"),
        "radius": Key(float, 0.06, lambda v: 0 < v < 1, "0 < value < 1 m, at least 1.5 cells "
                      "of the fluid grid", "coupled-fill: radius of the port stub below the "
                      "bottom pole (m)"),
        "length": Key(float, 0.065, lambda v: 0 < v < 1, "0 < value < 1 m, at least 2 cells of "
                      "the fluid grid", "coupled-fill: length of the port stub below the bottom "
                      "pole, where the flow enters (m)"),
        "ramp_time": Key(float, 0.1, _pos, "> 0 s",
                         "coupled-fill: the flow rises linearly from 0 over this time (s); a "
                         "valve opens in finite time, an impulsive start has no solution"),
    },
    "fluid": {
        "cells": Key(int, 16, lambda v: 8 <= v <= 128, "8..128",
                     "coupled-fill: cells per axis of the 3-D grid over the tank"),
        "viscosity": Key(float, 1e-3, lambda v: v >= 0, ">= 0 Pa s",
                         "coupled-fill: dynamic viscosity of the liquid (Pa s)"),
    },
    "coupling": {
        "scheme": Key(str, "implicit-serial", lambda v: v in SCHEMES,
                      ", ".join(repr(k) for k in sorted(SCHEMES)),
                      "coupled-fill: coupling scheme (membrane first, liquid second)"),
        "acceleration": Key(str, "iqn-ils", lambda v: v in ACCELERATIONS,
                            ", ".join(repr(k) for k in sorted(ACCELERATIONS)),
                            "coupled-fill: acceleration of the interface pressure"),
        "relaxation": Key(float, 0.01, lambda v: 0 < v <= 1, "0 < value <= 1",
                          "coupled-fill: constant under-relaxation factor"),
        "initial_relaxation": Key(float, 0.01, lambda v: 0 < v <= 1, "0 < value <= 1",
                                  "coupled-fill: Aitken's first factor of a window, IQN's first "
                                  "step"),
        "reuse": Key(int, 8, lambda v: 0 <= v <= 100, "0..100",
                     "coupled-fill: IQN past windows reused"),
        "filter_limit": Key(float, 1e-2, lambda v: 0 < v < 1, "0 < value < 1",
                            "coupled-fill: IQN QR2 filter"),
        "max_columns": Key(int, 100, lambda v: v >= 1, ">= 1",
                           "coupled-fill: IQN secant columns at most"),
        "pressure_tolerance": Key(float, 1e-4, lambda v: 0 < v < 1, "0 < value < 1",
                                  "coupled-fill: relative change of the interface pressure "
                                  "per iteration at convergence"),
        "position_tolerance": Key(float, 1e-6, lambda v: 0 < v < 1, "0 < value < 1",
                                  "coupled-fill: relative change of the node positions per "
                                  "iteration at convergence"),
        "max_iterations": Key(int, 60, lambda v: 1 <= v <= 10_000, "1..10000",
                              "coupled-fill: coupling iterations per window at most"),
        "on_max_iterations": Key(str, "error", lambda v: v in ON_MAX_ITERATIONS,
                                 ", ".join(repr(k) for k in ON_MAX_ITERATIONS),
                                 "coupled-fill: stop with an error, or accept the window and "
                                 "log it"),
        "extrapolation_order": Key(int, 0, lambda v: v in EXTRAPOLATION_WEIGHTS,
                                   ", ".join(str(k) for k in sorted(EXTRAPOLATION_WEIGHTS)),
                                   "coupled-fill: prediction of a window's start from past "
                                   "windows"),
    },
    "thesis": {
        "dt": Key(float, 1e-4, _pos, "> 0 s, below the explicit stability limit",
                  "time step (s) (thesis dt)"),
        "end_time": Key(float, 5.0, _pos, "> 0 s", "ramp duration (s) (thesis endtime)"),
        "height_start": Key(float, -1.05, lambda v: -10 <= v <= 10, "-10..10 (x radius)",
                            "initial equivalent height / radius (thesis -1.05)"),
        "height_end": Key(float, 1.05, lambda v: -10 <= v <= 10, "-10..10 (x radius)",
                          "final equivalent height / radius (thesis +1.05)"),
        "steady_state": Key(bool, True, lambda v: True, "true or false",
                            "reset acceleration each step (thesis SteadyState)"),
        "damping": Key(str, "courant-drag", lambda v: v in ("none", "critical", "courant-drag"),
                       "'none', 'critical' or 'courant-drag'", "damping mode (see README)"),
        "frame_interval": Key(int, 100, lambda v: v >= 1, ">= 1",
                              "steps between recorded frames (thesis 0.05 s / dt)"),
    },
}


@dataclass(frozen=True)
class Scene:
    """A validated scene: ``values[section][key]`` with defaults filled in, and the source text."""

    values: dict
    text: str
    source: str

    def __getitem__(self, section: str) -> dict:
        return self.values[section]

    @property
    def name(self) -> str:
        return self.values["scene"]["name"]


def _coerce(path: str, key: Key, value):
    if key.kind is float and isinstance(value, int) and not isinstance(value, bool):
        value = float(value)
    if key.kind is float and isinstance(value, float) and not math.isfinite(value):
        raise SceneError(f"scene key '{path}' = {value!r}: must be finite; allowed {key.allowed}")
    if not isinstance(value, key.kind) or (key.kind is not bool and isinstance(value, bool)):
        raise SceneError(f"scene key '{path}' = {value!r}: expected {key.kind.__name__}; "
                         f"allowed {key.allowed}")
    if not key.check(value):
        raise SceneError(f"scene key '{path}' = {value!r} is out of range; allowed {key.allowed}")
    return value


def parse_scene(text: str, source: str = "<string>") -> Scene:
    """Parse and validate scene TOML ``text``; raises :class:`SceneError`."""
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"{source}: not valid TOML: {exc}") from None
    values: dict = {}
    for section, value in raw.items():
        if section not in SCHEMA:
            raise SceneError(f"unknown scene section '[{section}]'; allowed: "
                             f"{', '.join(SCHEMA)}")
        if not isinstance(value, dict):
            raise SceneError(f"scene key '{section}' must be a table [{section}]")
        for name in value:
            if name not in SCHEMA[section]:
                raise SceneError(f"unknown scene key '{section}.{name}'; allowed in "
                                 f"[{section}]: {', '.join(SCHEMA[section])}")
    for section, keys in SCHEMA.items():
        given = raw.get(section, {})
        values[section] = {name: (_coerce(f"{section}.{name}", key, given[name])
                                  if name in given else key.default)
                           for name, key in keys.items()}
    _check_cross(values)
    return Scene(values, text, source)


def _check_cross(values: dict) -> None:
    th = values["thesis"]
    steps = th["end_time"] / th["dt"]
    if steps > 5e7:
        raise SceneError(f"scene key 'thesis.dt' = {th['dt']!r}: end_time/dt = {steps:.3g} steps; "
                         f"allowed at most 5e7")
    if (values["scene"]["procedure"] == "thesis-ramp"
            and values["structure"]["model"] not in ("auto", "thesis")):
        raise SceneError(f"scene key 'structure.model' = {values['structure']['model']!r}: the "
                         f"thesis-ramp procedure runs the thesis model only; allowed 'auto' or "
                         f"'thesis'")
    if (values["scene"]["procedure"] == "coupled-fill"
            and values["structure"]["model"] not in ("auto", "xpbd")):
        raise SceneError(f"scene key 'structure.model' = {values['structure']['model']!r}: the "
                         f"coupled-fill procedure runs the xpbd model (the dynamic membrane); "
                         f"allowed 'auto' or 'xpbd'")
    motion = values["motion"]
    if motion["kind"] == "table" and len(motion["history"]) < 2:
        raise SceneError(f"scene key 'motion.history' = {motion['history']!r}: motion.kind = "
                         f"'table' needs at least two rows [t, ax, ay, az]")
    dyn = values["dynamics"]
    windows = dyn["end_time"] / dyn["window"]
    if values["scene"]["procedure"] == "coupled-fill" and windows > 1e6:
        raise SceneError(f"scene key 'dynamics.window' = {dyn['window']!r}: end_time/window = "
                         f"{windows:.3g} windows; allowed at most 1e6")
    if values["scene"]["procedure"] == "volume-sweep" and len(values["sweep"]["fills"]) < 1:
        raise SceneError("scene key 'sweep.fills' is empty; allowed: at least one fill in [0, 1]")


def bundled_scenes() -> list[str]:
    """Names of the scenes shipped in ``fsi/scenes``."""
    return sorted(p.name[:-5] for p in resources.files("fsi.scenes").iterdir()
                  if p.name.endswith(".toml"))


def load_scene(name_or_path: str) -> Scene:
    """Load a bundled scene by name, or a scene file by path; validates it."""
    path = Path(name_or_path)
    if path.suffix == ".toml" or path.exists():
        if not path.is_file():
            raise SceneError(f"scene file '{path}' not found")
        return parse_scene(path.read_text(), str(path))
    if name_or_path not in bundled_scenes():
        raise SceneError(f"unknown scene '{name_or_path}': not a file, and not one of the bundled "
                         f"scenes {bundled_scenes()}")
    text = resources.files("fsi.scenes").joinpath(f"{name_or_path}.toml").read_text()
    return parse_scene(text, f"bundled:{name_or_path}")


def reference_markdown() -> str:
    """Scene reference table (Markdown) generated from :data:`SCHEMA`."""
    lines = ["| key | default | allowed | meaning |", "|---|---|---|---|"]
    for section, keys in SCHEMA.items():
        for name, key in keys.items():
            default = "solver default" if key.default is None else repr(key.default)
            lines.append(f"| `{section}.{name}` | {default} | {key.allowed} | {key.doc} |")
    return "\n".join(lines)
