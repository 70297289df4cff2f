"""The procedures a scene can run, one record each, and the vocabulary of scene keys.

A procedure is one :class:`Procedure` record: its name (the scene's ``scene.procedure``), a
one-line summary, the scene tables it owns (keys with defaults and checks), the structure
model it needs, its setup checks, what ``fsi run`` prints after it, and its run
function. Adding a procedure is adding one module under :mod:`fsi.procedures` that calls
:func:`register_procedure`; the scene schema, the build and the CLI read everything from here.

This module imports nothing of the project, so every other module may import it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Optional

import numpy as np


class SceneError(ValueError):
    """A scene file is malformed: the message names the key, the value and the allowed range."""


@dataclass(frozen=True)
class Key:
    """One scene key: Python type, default, check (value -> bool), allowed range text, doc."""

    kind: type
    default: Any
    check: Callable[[Any], bool]
    allowed: "str | Names"
    doc: str


def _nothing(_) -> None:
    return None


class Table(dict):
    """A scene table: key name -> :class:`Key`, and ``check``, a check of the table's values
    together ({key: value} -> None, raising :class:`SceneError`), run on every scene."""

    def __init__(self, keys: Mapping[str, Key], check: Callable[[dict], None] = _nothing):
        super().__init__(keys)
        self.check = check


def positive(v) -> bool:
    return v > 0


def check_sn_curve(points) -> str | None:
    """Why ``points`` is not an S-N curve (text), or None: at least two [range Pa > 0,
    cycles > 0] pairs, the range falling strictly as the cycles rise strictly."""
    try:
        a = np.asarray(points, dtype=float)
    except (TypeError, ValueError):
        return "pairs of numbers"
    if a.size == 0:
        return None
    if a.ndim != 2 or a.shape[1] != 2 or len(a) < 2:
        return "at least two [stress range Pa, cycles] pairs"
    if not np.all(np.isfinite(a)) or np.any(a <= 0):
        return "positive, finite stress ranges and cycles"
    if np.any(np.diff(a[:, 0]) >= 0) or np.any(np.diff(a[:, 1]) <= 0):
        return "stress ranges falling and cycles rising from one pair to the next"
    return None


def is_vec3(v) -> bool:
    """Three finite numbers."""
    return isinstance(v, list) and len(v) == 3 and all(
        isinstance(c, (int, float)) and not isinstance(c, bool) and math.isfinite(c) for c in v)


def is_band(v) -> bool:
    """Two finite numbers 0 <= start < stop <= 1."""
    return (isinstance(v, list) and len(v) == 2
            and all(isinstance(c, (int, float)) and not isinstance(c, bool) for c in v)
            and 0 <= v[0] < v[1] <= 1)


class Names:
    """The allowed text of a key whose value is one of ``names``, read when printed, so that
    a registry filled after the schema is built (a surface registered by another module) is
    listed whole."""

    def __init__(self, names):
        self.names = names

    def __str__(self) -> str:
        return ", ".join(repr(k) for k in self.names)

    def __format__(self, spec: str) -> str:
        return format(str(self), spec)


def one_of(names) -> tuple[Callable[[Any], bool], Names]:
    """(check, allowed text) of a key whose value is one of ``names`` (a registry or a
    sequence; both read it when called)."""
    return (lambda v: v in names), Names(names)


def short_number(x: float) -> str:
    """A round limit as written in a scene reference: 1000000.0 -> '1e6'."""
    return f"{x:.0e}".replace("e+0", "e").replace("e+", "e")


@dataclass(frozen=True)
class Procedure:
    """One procedure.

    name, summary : registry key and one line for listings; run : (setup, progress) ->
    :class:`fsi.lifecycle.RunResult`; tables : {table name: :data:`Table`} the procedure owns
    (a table may be shared by procedures as the same object); structure_model : the only
    structure model it runs (the scene may say it or 'auto'), None for any; membrane_shapes :
    the ``membrane.shape`` values it runs; check_setup :
    checks that need the built setup (grid spacings, stability limits), raising
    :class:`SceneError`; report : prints the result's summary; headline : prints what
    ``fsi show`` says of a written result beside its record counts (the modes' frequencies
    and slosh masses of a modes or slosh run), nothing for the others; holds_volume : its
    membrane frames hold the liquid volume of the first, the static start (a slosh run), so
    that the static model at their volume is that frame.
    """

    name: str
    summary: str
    run: Callable
    tables: Mapping[str, Table] = field(default_factory=dict)
    structure_model: Optional[str] = None
    membrane_shapes: tuple = ("hemisphere",)
    check_setup: Callable[[Any], None] = _nothing
    report: Callable[[Any], None] = _nothing
    headline: Callable[[Any], None] = _nothing
    holds_volume: bool = False

    def __call__(self, setup, progress):
        """Run the procedure: ``progress(fraction, message)`` is called as it goes. A run
        interrupted between units of work (:class:`fsi.lifecycle.Interrupted`), or stopped by
        a solver's error the procedure did not handle (:func:`solver_failures`), returns
        what it recorded, with ``interrupted`` (the signal's number) or ``solver_failure``
        (the error's type) and ``failure`` set; such an error before the run started raises
        :class:`StartFailure`."""
        from fsi.lifecycle import Interrupted, Run

        Run.current = None
        try:
            return self.run(setup, progress)
        except Interrupted as stop:
            stop.run.failure = f"interrupted by signal {stop.signal}"
            return stop.run.result(interrupted=stop.signal)
        except solver_failures() as err:
            if Run.current is None:
                raise StartFailure(f"{type(err).__name__}: {err}") from err
            Run.current.failure = f"{type(err).__name__}: {err}"
            return Run.current.result(solver_failure=type(err).__name__)


class StartFailure(Exception):
    """A solver's error before the run recorded anything (e.g. in a static sweep's full
    inversion): there is nothing to write; ``fsi run`` says so in one line, exit 1."""


def solver_failures() -> tuple:
    """Errors of the solvers that end a run (time step, divergence, coupling), as opposed to
    errors in the code."""
    from coupling import CouplingError
    from structure.newton.dynamics import NewtonDivergence
    from structure.thesis import CourantError
    from structure.xpbd import XpbdDivergence

    return CourantError, XpbdDivergence, NewtonDivergence, CouplingError


PROCEDURES: dict[str, Procedure] = {}


def register_procedure(procedure: Procedure) -> Procedure:
    """Add ``procedure`` to :data:`PROCEDURES`; a table it shares with a registered procedure
    must be the same table."""
    if procedure.name in PROCEDURES:
        raise ValueError(f"procedure {procedure.name!r} is registered twice")
    for other in PROCEDURES.values():
        for name, table in procedure.tables.items():
            if name in other.tables and other.tables[name] is not table:
                raise ValueError(f"procedures {other.name!r} and {procedure.name!r} define "
                                 f"different tables [{name}]")
    PROCEDURES[procedure.name] = procedure
    return procedure
