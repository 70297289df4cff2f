"""Scene files (TOML): schema, defaults and validation.

A scene is a TOML file of tables. The tables every scene shares are defined here; each
procedure owns the tables only it uses (:mod:`fsi.procedures`, read from the registry
:mod:`fsi.registry`). Every key has a type, a default and an allowed range; unknown keys, wrong
types and out-of-range values raise :class:`SceneError` naming the key, the value and what is
allowed, before anything is computed or written. The schema is the single place where
defaults live; the scene-key reference (docs/user-guide/scenes.md, 'Scene file reference') is
generated from it (``fsi scenes --reference``).
"""
from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, replace
from importlib import resources
from pathlib import Path

from structure.model import MEMBRANE_SHAPES, SUPPORTS
from structure.shell import MEMBRANE_LAWS
from structure.xpbd.model import WRINKLING

from fsi import constants
from fsi import procedures  # noqa: F401  (fills the registry)
from fsi.setup.models import STRUCTURE_MODELS
from fsi.registry import (PROCEDURES, Key, SceneError, Table, check_sn_curve, is_band, is_vec3,
                          one_of, positive)
from fsi.text import closest, unknown_name

__all__ = ["SCHEMA", "Scene", "SceneError", "bundled_scenes", "load_scene", "parse_scene",
           "reference_markdown"]

COMMON: dict[str, Table] = {
    "scene": Table({
        "name": Key(str, "unnamed", lambda v: len(v) > 0, "non-empty text", "scene name"),
        "description": Key(str, "", lambda v: True, "any text", "one-line description"),
        "procedure": Key(str, "volume-sweep", *one_of(list(PROCEDURES)),
                         "; ".join(f"{p.name}: {p.summary}" for p in PROCEDURES.values())),
    }),
    "tank": Table({
        "radius": Key(float, constants.TANK_RADIUS, positive, "> 0 m",
                      "spherical tank radius (m)"),
    }),
    "membrane": Table({
        "grid_size": Key(int, 26, lambda v: v >= 4 and v % 2 == 0, "even integer >= 4",
                         "nodes per grid side (thesis GridSize)"),
        "thickness": Key(float, constants.MEMBRANE_THICKNESS, positive, "> 0 m",
                         "membrane thickness (m)"),
        "density": Key(float, constants.MEMBRANE_DENSITY, positive, "> 0 kg/m^3",
                       "membrane density (kg/m^3)"),
        "youngs_modulus": Key(float, constants.MEMBRANE_YOUNGS_MODULUS, positive, "> 0 Pa",
                              "Young's modulus (Pa)"),
        "poisson_ratio": Key(float, 0.5, lambda v: 0 <= v <= 0.5, "0..0.5",
                             "Poisson ratio (xpbd and shell models; rubber 0.5)"),
        "shape": Key(str, "hemisphere", *one_of(list(MEMBRANE_SHAPES)),
                     "rest shape: the thesis's hemisphere against the lower tank wall, or a "
                     "flat disc across the equator (thesis Ch. 3; " + ", ".join(
                         p.name for p in PROCEDURES.values() if "disc" in p.membrane_shapes)
                     + " only)"),
        "support": Key(str, "clamped", *one_of(list(SUPPORTS)),
                       "rim support: two fixed rings (clamped, thesis App. B: the free sheet's "
                       "rim one grid edge inside r = R) or one on r = R (simply-supported; the "
                       "xpbd and shell models' bending still holds the rim's slope)"),
        "grading_band": Key(list, [0.0, 1.0], is_band, "two numbers 0 <= start < stop <= 1",
                            "the band of the rest meridian (fractions of its arc from the "
                            "pole, 0, to the rim, 1; of r / R on the disc) given "
                            "grading_density times the rings per unit length of the rest of "
                            "the meridian (docs/notes/graded-grid.md)"),
        "grading_density": Key(float, 1.0, lambda v: math.isfinite(v) and v >= 1, ">= 1",
                               "node density inside grading_band over outside it, the nodes "
                               "moved along their meridians (1: the App. C grid unchanged)"),
        "wrinkling": Key(str, "none", *one_of(list(WRINKLING)),
                         "in-plane law of the xpbd model: 'tension-field' carries no "
                         "compression (a sheet too coarse to fold wrinkles instead of "
                         "locking; docs/notes/tension-field.md)"),
    }),
    "structure": Table({
        "model": Key(str, "auto", *one_of(["auto", *STRUCTURE_MODELS]),
                     "membrane model of a volume sweep (docs/user-guide/choosing-a-model.md); "
                     "auto: the cheapest meeting structure.accuracy; a procedure that runs one "
                     "model only takes it (" + ", ".join(
                         f"{p.name}: {p.structure_model}" for p in PROCEDURES.values()
                         if p.structure_model) + ")"),
        "accuracy": Key(float, 5.0, lambda v: 0 < v <= 100, "0 < value <= 100 (%)",
                        "Eqn 6.1 error the scene accepts, for model = 'auto' (%)"),
        "shell_law": Key(str, "saint-venant-kirchhoff", *one_of(MEMBRANE_LAWS),
                         "membrane law of the shell model"),
    }),
    "liquid": Table({
        "density": Key(float, constants.WATER_DENSITY, positive, "> 0 kg/m^3",
                       "liquid density (kg/m^3)"),
        "body_acceleration": Key(list, [0.0, 0.0, -constants.STANDARD_GRAVITY], is_vec3,
                                 "three finite numbers (m/s^2)",
                                 "gravity minus tank acceleration, tank frame (m/s^2)"),
    }),
    "constraints": Table({
        "error_limit": Key(float, 1.0, lambda v: 0 < v < 100, "0 < value < 100 (%)",
                           "in-plane strain limit (thesis ErrorLimit, %)"),
        "bend_limit_iterations": Key(int, 10, lambda v: 0 <= v <= 1000, "0..1000",
                                     "bend-limiting passes per step (thesis BendDamping); "
                                     "thesis-ramp only, the static sweep runs without "
                                     "(docs/models/thesis-membrane.md)"),
        "self_collision": Key(bool, False, lambda v: True, "true or false",
                              "self-collision (thesis CollisionDetection), both static "
                              "procedures (the sweep is ~8x slower with it, "
                              "docs/models/thesis-membrane.md)"),
        "collision_buffer": Key(float, 1.0, lambda v: 0 < v <= 1, "0 < value <= 1",
                                "collision distance / shortest rest edge (thesis Cbuffer)"),
        "constraint_iterations": Key(int, 1, lambda v: 1 <= v <= 100, "1..100",
                                     "constraint rounds per step (thesis "
                                     "ConstraintIterations); thesis-ramp only"),
    }),
    "fatigue": Table({
        "sn_curve": Key(list, [], lambda v: check_sn_curve(v) is None,
                        "empty, or at least two [stress range Pa, cycles] pairs, the range "
                        "falling as the cycles rise",
                        "S-N curve of the diaphragm's material for Miner's damage per run "
                        "(fsi.analysis.fatigue); none is assumed"),
        "peak_triangles": Key(int, 5, lambda v: 1 <= v <= 1000, "1..1000",
                              "triangles of largest peak stress whose stress history is "
                              "rainflow-counted"),
    }),
    "limits": Table({
        "stress": Key(float, 0.0, lambda v: v >= 0, ">= 0 Pa (0: none)",
                      "allowable surface stress of the diaphragm's material: the result's "
                      "stress_margin is it over the run's peak; none is assumed"),
        "strain": Key(float, 0.0, lambda v: v >= 0, ">= 0 (0: none)",
                      "allowable principal logarithmic strain: the result's strain_margin is "
                      "it over the run's peak; none is assumed"),
    }),
}
"""Tables every scene shares: the scene, the tank, the membrane and its structure model, the
liquid at rest, the thesis membrane's constraints, the fatigue data and the material's
limits."""


def _schema() -> dict[str, Table]:
    schema = dict(COMMON)
    for procedure in PROCEDURES.values():
        for name, table in procedure.tables.items():
            if name in COMMON:
                raise ValueError(f"procedure {procedure.name!r} redefines the common table "
                                 f"[{name}]")
            schema.setdefault(name, table)
    return schema


SCHEMA: dict[str, Table] = _schema()
"""Every table a scene may hold: :data:`COMMON`, then the procedures' own tables."""


def owners(table: str) -> list[str]:
    """Names of the procedures that own ``table`` (empty for a common table)."""
    return [p.name for p in PROCEDURES.values() if table in p.tables]


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

    def with_keys(self, changes: dict) -> "Scene":
        """This scene with ``changes`` = {section: {key: value}} applied, each value checked
        as a scene file's is (raises :class:`SceneError` naming the key); ``text`` stays the
        source's."""
        values = {section: dict(keys) for section, keys in self.values.items()}
        for section, keys in changes.items():
            check_known(section, keys)
            for name, value in keys.items():
                values[section][name] = _coerce(f"{section}.{name}", SCHEMA[section][name],
                                                value)
            SCHEMA[section].check(values[section])
        _check_procedure(values)
        return replace(self, values=values)


def check_known(section: str, names) -> None:
    """:class:`SceneError` for a table ``[section]`` or a key of ``names`` in it that the
    schema does not know, naming it, the closest known name and the names allowed."""
    if section not in SCHEMA:
        raise SceneError(f"unknown scene section '[{section}]'"
                         + _hint(section_suggestion(section)) + f" allowed: {', '.join(SCHEMA)}")
    for name in names:
        if name not in SCHEMA[section]:
            raise SceneError(f"unknown scene key '{section}.{name}'"
                             + _hint(key_suggestion(section, name))
                             + f" allowed in [{section}]: {', '.join(SCHEMA[section])}")


def _hint(text: str) -> str:
    """'; did you mean ...?' after a name, or ';' when there is no suggestion."""
    return f"; {text}" if text else ";"


def section_suggestion(section: str) -> str:
    """"did you mean '[table]'?" for an unknown table: the closest table, else the table
    holding a key of that name (a key written outside its table); '' when there is
    neither."""
    match = closest(section, SCHEMA)
    if match:
        return f"did you mean '[{match}]'?"
    holders = [table for table, keys in SCHEMA.items() if section in keys]
    return f"did you mean '{holders[0]}.{section}', under [{holders[0]}]?" if holders else ""


def key_suggestion(section: str, name: str) -> str:
    """"did you mean 'section.key'?" for an unknown key ``name`` of ``[section]``: the
    closest key of that table, else the same key in another table; '' when there is
    neither."""
    match = closest(name, SCHEMA[section])
    if match:
        return f"did you mean '{section}.{match}'?"
    elsewhere = [other for other, keys in SCHEMA.items() if name in keys]
    return f"did you mean '{elsewhere[0]}.{name}'?" if elsewhere else ""


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
        if section in SCHEMA and not isinstance(value, dict):
            raise SceneError(f"scene key '{section}' must be a table [{section}]")
        check_known(section, value)
    for section, keys in SCHEMA.items():
        given = raw.get(section, {})
        values[section] = {name: (_coerce(f"{section}.{name}", key, given[name])
                                  if name in given else key.default)
                           for name, key in keys.items()}
        keys.check(values[section])
    _check_procedure(values)
    return Scene(values, text, source)


def _check_procedure(values: dict) -> None:
    """What the scene's procedure runs: its structure model and its membrane shapes."""
    _check_structure_model(values)
    _check_membrane_shape(values)


def _check_structure_model(values: dict) -> None:
    """A procedure that runs one structure model only takes it or 'auto'."""
    procedure = PROCEDURES[values["scene"]["procedure"]]
    needed, model = procedure.structure_model, values["structure"]["model"]
    if needed is not None and model not in ("auto", needed):
        raise SceneError(f"scene key 'structure.model' = {model!r}: the {procedure.name} "
                         f"procedure runs the {needed} model only; allowed 'auto' or "
                         f"'{needed}'")


def _check_membrane_shape(values: dict) -> None:
    """A procedure runs the membrane shapes it lists only."""
    procedure = PROCEDURES[values["scene"]["procedure"]]
    shape, allowed = values["membrane"]["shape"], procedure.membrane_shapes
    if shape not in allowed:
        raise SceneError(f"scene key 'membrane.shape' = {shape!r}: the {procedure.name} "
                         f"procedure runs {', '.join(map(repr, allowed))} only")


def bundled_scenes() -> list[str]:
    """Names of the scenes shipped in ``fsi/scenes``."""
    return sorted(p.name[:-5] for p in resources.files("fsi.scenes").iterdir()
                  if p.name.endswith(".toml"))


def load_scene(name_or_path: str) -> Scene:
    """Load a scene file by path, or a bundled scene by name; validates it. A path wins only
    when it is a file (or names a .toml): a folder named like a bundled scene does not hide
    it."""
    path = Path(name_or_path)
    if path.is_file() or (path.suffix == ".toml" and name_or_path not in bundled_scenes()):
        if not path.is_file():
            raise SceneError(f"scene file '{path}' not found")
        return parse_scene(read_text(path), str(path))
    if name_or_path not in bundled_scenes():
        raise SceneError(unknown_name("scene", name_or_path, bundled_scenes(), "fsi scenes"))
    return parse_scene(bundled_text(name_or_path), f"bundled:{name_or_path}")


def read_text(path: Path) -> str:
    """A scene file's text: UTF-8, not empty (:class:`SceneError` naming the file)."""
    data = path.read_bytes()
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as err:
        raise SceneError(f"scene file '{path}' is not UTF-8 text (byte {err.start}); save it "
                         f"as UTF-8 TOML") from None
    if "\x00" in text:
        raise SceneError(f"scene file '{path}' holds NUL characters: not a TOML text file")
    if not tomllib_loads_anything(text):
        raise SceneError(f"scene file '{path}' is empty: start from a bundled scene, e.g. "
                         f"'fsi scenes thesis-static > {path.name}'")
    return text


def tomllib_loads_anything(text: str) -> bool:
    """Whether ``text`` holds anything but blanks and comments (invalid TOML counts: its
    error is parse_scene's to name)."""
    try:
        return bool(tomllib.loads(text))
    except tomllib.TOMLDecodeError:
        return True


def bundled_text(name: str) -> str:
    """The TOML text of bundled scene ``name``."""
    if name not in bundled_scenes():
        raise SceneError(unknown_name("scene", name, bundled_scenes(), "fsi scenes"))
    return resources.files("fsi.scenes").joinpath(f"{name}.toml").read_text()


def reference_markdown() -> str:
    """Scene reference table (Markdown) generated from :data:`SCHEMA`: the common tables,
    then each procedure's own, the procedures that use a table named beside its keys."""
    lines = ["| key | default | allowed | meaning |", "|---|---|---|---|"]
    for section, keys in SCHEMA.items():
        used_by = owners(section)
        scope = f" ({', '.join(used_by)})" if used_by else ""
        for name, key in keys.items():
            default = "solver default" if key.default is None else repr(key.default)
            lines.append(f"| `{section}.{name}` | {default} | {key.allowed} | {key.doc}{scope} |")
    return "\n".join(lines)
