"""Sweep files (TOML): a base scene and the scene keys to vary, expanded into cases::

    [sweep]
    name = "slosh-by-fill"
    scene = "slosh-half"          # a bundled scene, or a scene file (relative to this file)
    plot = ["lambda1", "zeta"]    # result quantities plotted against the swept keys
    reference = { slosh.fill = 0.5 }  # optional: the case whose membrane shapes the others'
                                  # are compared with by Eqn 6.1, picked by swept keys' values

    [set]                         # every case: these keys fixed (scene key = value)
    slosh.end_time = 3.0

    [vary]                        # the product of these axes, one axis per key:
    slosh.fill = [0.1, 0.5, 0.9]                      # a list of values, or
    motion.frequency = {start = 1.0, stop = 2.0, num = 3}     # a range (inclusive;
                                                      # or step = 0.5 instead of num)

    [zip.model]                   # keys varied together along one axis (here "model"):
    slosh.surface = ["limp", "diaphragm"]             # lists of one length
    slosh.end_time = [5.0, 1.5]

Keys are scene keys ``table.key`` (TOML dotted keys). A vector key (e.g.
``motion.amplitude``) varies over a list of vectors. Every case's scene is built and checked
as ``fsi run`` would (:func:`fsi.setup.build.build`) before anything runs: a bad combination is one
:class:`SweepError` naming its key and value.
"""
from __future__ import annotations

import itertools
import tomllib
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

import numpy as np

from fsi.registry import SceneError
from fsi.text import closest, unknown_name

SWEEP_TABLES = ("sweep", "set", "vary", "zip")
SWEEP_KEYS = ("name", "description", "scene", "plot", "reference")


class SweepError(SceneError):
    """A sweep file that cannot run: one line naming the file, key or case."""


@dataclass(frozen=True)
class Axis:
    """One axis of a sweep: its name (the key, or the zip table's name) and, per key varied
    along it, the values (all of one length)."""

    name: str
    values: dict[str, list]

    @property
    def size(self) -> int:
        return len(next(iter(self.values.values())))


@dataclass(frozen=True)
class Case:
    """One case: its folder name, its index along each axis and its scene keys' values."""

    name: str
    index: tuple[int, ...]
    keys: dict
    scene_text: str


@dataclass
class Sweep:
    """A parsed sweep: its name, description, the base scene's source, the fixed keys, the
    axes (product order), the quantities to plot, its text, its cases and the name of the
    reference case ('' when none)."""

    name: str
    description: str
    scene: str
    fixed: dict
    axes: list[Axis]
    plot: list[str]
    text: str
    cases: list[Case] = field(default_factory=list)
    reference: str = ""

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(a.size for a in self.axes)


def flatten(table: dict, prefix: str = "") -> dict:
    """{"slosh": {"fill": v}} -> {"slosh.fill": v} (two levels: scene table and key)."""
    out = {}
    for name, value in table.items():
        key = f"{prefix}{name}"
        if isinstance(value, dict) and not prefix and not _is_range(value):
            out.update(flatten(value, f"{key}."))
        else:
            out[key] = value
    return out


def _is_range(value) -> bool:
    return isinstance(value, dict) and "start" in value and "stop" in value


def expand(key: str, value) -> list:
    """The values of ``key`` along its axis: a list as given, or a range table
    {start, stop, num} / {start, stop, step} (stop included), rounded to 12 digits."""
    if isinstance(value, list):
        if not value:
            raise SweepError(f"sweep key '{key}': an empty list; give at least one value")
        return value
    if not _is_range(value) or len(set(value) & {"num", "step"}) != 1 or \
            set(value) - {"start", "stop", "num", "step"}:
        raise SweepError(f"sweep key '{key}' = {value!r}: give a list of values, or "
                         "{start, stop, num} or {start, stop, step}")
    start, stop = float(value["start"]), float(value["stop"])
    if "num" in value:
        num = value["num"]
        if not isinstance(num, int) or num < 1:
            raise SweepError(f"sweep key '{key}.num' = {num!r}: allowed an integer >= 1")
    else:
        step = float(value["step"])
        if not step > 0 or stop < start:
            raise SweepError(f"sweep key '{key}.step' = {step!r}: allowed > 0 with "
                             f"stop >= start")
        num = int(np.floor((stop - start) / step + 1e-9)) + 1
        stop = start + (num - 1) * step
    return [float(f"{v:.12g}") for v in np.linspace(start, stop, num)]


def _axes(raw: dict, source: str) -> list[Axis]:
    axes = [Axis(key, {key: expand(key, value)})
            for key, value in flatten(raw.get("vary", {})).items()]
    for name, table in raw.get("zip", {}).items():
        if not isinstance(table, dict) or not table:
            raise SweepError(f"{source}: [zip.{name}] must be a table of keys and lists")
        values = {key: expand(f"zip.{name}.{key}", v) for key, v in flatten(table).items()}
        sizes = {len(v) for v in values.values()}
        if len(sizes) != 1:
            raise SweepError(f"{source}: the lists of [zip.{name}] differ in length "
                             f"({', '.join(f'{k}: {len(v)}' for k, v in values.items())})")
        axes.append(Axis(name, values))
    if not axes:
        raise SweepError(f"{source}: nothing to vary; give [vary] or [zip.NAME] keys")
    keys = [k for a in axes for k in a.values]
    repeated = sorted({k for k in keys if keys.count(k) > 1})
    if repeated:
        raise SweepError(f"{source}: key '{repeated[0]}' is varied on two axes")
    return axes


def parse_sweep(text: str, source: str = "<string>", base: Path | None = None) -> Sweep:
    """Parse a sweep file's ``text`` (scene files relative to ``base``) and build every case
    (:func:`build_cases`); raises :class:`SweepError`."""
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise SweepError(f"{source}: not valid TOML: {err}") from None
    check_known(raw, source)
    head = raw.get("sweep", {})
    if not isinstance(head.get("scene"), str):
        raise SweepError(f"{source}: 'sweep.scene' names the base scene (bundled name or "
                         "file); it is missing")
    scene = head["scene"]
    if base is not None and not Path(scene).is_absolute() and (base / scene).is_file():
        scene = str(base / scene)
    sweep = Sweep(name=str(head.get("name", Path(source).stem)),
                  description=str(head.get("description", "")), scene=scene,
                  fixed=flatten(raw.get("set", {})), axes=_axes(raw, source),
                  plot=list(head.get("plot", ["run_seconds"])), text=text)
    sweep.cases = build_cases(sweep)
    sweep.reference = reference_case(sweep, head.get("reference"), source)
    return sweep


def check_known(raw: dict, source: str) -> None:
    """:class:`SweepError` for a table of the sweep file, or a key of its [sweep] table, that
    a sweep file does not have, naming it, the closest known name and the names allowed."""
    _refuse_unknown(set(raw), SWEEP_TABLES, source, "table [{}]", "[{}]")
    head = raw.get("sweep", {})
    if not isinstance(head, dict):
        raise SweepError(f"{source}: 'sweep' must be a table [sweep]")
    _refuse_unknown(set(head), SWEEP_KEYS, source, "key 'sweep.{}'", "'sweep.{}'")


def _refuse_unknown(names: set, known, source: str, what: str, quoted: str) -> None:
    """:class:`SweepError` for the first of ``names`` not in ``known``: ``what`` and
    ``quoted`` format it in the message (the unknown name, the closest known one)."""
    unknown = sorted(names - set(known))
    if unknown:
        match = closest(unknown[0], known)
        raise SweepError(f"{source}: unknown {what.format(unknown[0])}"
                         + (f"; did you mean {quoted.format(match)}?" if match else ";")
                         + f" allowed: {', '.join(known)}")


def reference_case(sweep: Sweep, keys, source: str) -> str:
    """The name of the one case whose keys take the values in ``keys`` (a table of swept
    keys; None: no reference)."""
    if keys is None:
        return ""
    swept = {k for a in sweep.axes for k in a.values}
    keys = flatten(keys) if isinstance(keys, dict) else keys
    if not isinstance(keys, dict) or not keys or set(keys) - swept:
        raise SweepError(f"{source}: 'sweep.reference' = {keys!r}: give a table of swept keys "
                         f"and values ({', '.join(sorted(swept))})")
    matches = [c.name for c in sweep.cases if all(c.keys[k] == v for k, v in keys.items())]
    if len(matches) != 1:
        raise SweepError(f"{source}: 'sweep.reference' = {keys!r} picks {len(matches)} cases; "
                         "give values that pick one")
    return matches[0]


def build_cases(sweep: Sweep) -> list[Case]:
    """Every combination of the axes as a :class:`Case` whose scene is the base scene with
    the fixed and the case's keys set, each built and checked as ``fsi run`` would."""
    from fsi.scene import load_scene

    base = tomllib.loads(load_scene(sweep.scene).text)
    short = short_names([k for a in sweep.axes for k in a.values])
    cases = []
    for index in itertools.product(*(range(a.size) for a in sweep.axes)):
        keys = {k: v[i] for a, i in zip(sweep.axes, index) for k, v in a.values.items()}
        name = case_name({short[k]: v for k, v in keys.items()})
        cases.append(Case(name, index, keys,
                          case_scene(base, {**sweep.fixed, **keys}, sweep.name, name)))
    for case in cases:
        check_case(case)
    return cases


def short_names(keys: list[str]) -> dict[str, str]:
    """{key: its name in case names}: the key without its table ('fill' for 'slosh.fill')
    where no other swept key ends the same, else the whole key."""
    tails = [k.rpartition(".")[2] for k in keys]
    return {k: t if tails.count(t) == 1 else k for k, t in zip(keys, tails)}


def case_name(keys: dict) -> str:
    """The case's folder name from its keys' values: 'fill=0.5,surface=limp'."""
    def text(v):
        return "x".join(map(text, v)) if isinstance(v, list) else f"{v:g}" \
            if isinstance(v, float) else str(v)
    return ",".join(f"{k}={text(v)}" for k, v in keys.items()).replace("/", "_")


def case_scene(base: dict, keys: dict, sweep_name: str, name: str) -> str:
    """The TOML text of the base scene with ``keys`` set, named 'SWEEP[case name]'."""
    import tomli_w

    raw = {table: dict(values) for table, values in base.items()}
    for key, value in keys.items():
        table, _, name = key.partition(".")
        if not name:
            raise SweepError(f"sweep key '{key}': give a scene key as table.key")
        raw.setdefault(table, {})[name] = value
    raw.setdefault("scene", {})["name"] = f"{sweep_name}[{name}]"
    return tomli_w.dumps(raw)


def check_case(case: Case) -> None:
    """Build the case's scene as ``fsi run`` would; :class:`SweepError` naming the case's
    keys and the scene's complaint."""
    from fsi.setup.build import build
    from fsi.scene import parse_scene

    try:
        build(parse_scene(case.scene_text, case.name))
    except SceneError as err:
        raise SweepError(f"sweep case {case.name}: {err}") from None


def bundled_sweeps() -> list[str]:
    """Names of the sweeps shipped in ``fsi/sweeps``."""
    return sorted(p.name[:-5] for p in resources.files("fsi.sweeps").iterdir()
                  if p.name.endswith(".toml"))


def bundled_sweep_text(name: str) -> str:
    """The TOML text of the bundled sweep ``name``; :class:`SweepError` when there is none."""
    if name not in bundled_sweeps():
        raise SweepError(unknown_name("sweep", name, bundled_sweeps(), "fsi sweeps"))
    return resources.files("fsi.sweeps").joinpath(f"{name}.toml").read_text()


def load_sweep(name_or_path: str) -> Sweep:
    """A sweep file by path, or a bundled sweep by name, parsed and every case checked."""
    path = Path(name_or_path)
    if path.is_file():
        from fsi.scene import read_text

        return parse_sweep(read_text(path), str(path), path.resolve().parent)
    if name_or_path not in bundled_sweeps():
        raise SweepError(unknown_name("sweep", name_or_path, bundled_sweeps(),
                                      "fsi sweeps"))
    return parse_sweep(bundled_sweep_text(name_or_path), f"bundled:{name_or_path}")
