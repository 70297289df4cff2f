"""What the coupling sees of a solver: a small participant protocol (after preCICE's calls).

A participant owns some named interface fields (flat float64 vectors of any size). Per time
window the coupling scheme gives it the partner's fields and asks it to advance; it returns its
own fields at the end of the window. For implicit schemes the scheme stores a checkpoint at the
start of the window and restores it before every repeated solve.
"""
from __future__ import annotations

from typing import Any, Mapping, Protocol, runtime_checkable

import numpy as np

Fields = Mapping[str, np.ndarray]
"""Named interface data: {field name: flat float64 array}."""


@runtime_checkable
class Participant(Protocol):
    """A solver as the coupling sees it.

    name : label used in logs.
    write_fields : names of the fields this participant produces (read by the partner).
    """

    name: str
    write_fields: tuple[str, ...]

    def initial_data(self) -> Fields:
        """The fields this participant writes, at the initial time (before any window)."""

    def solve_window(self, time: float, dt: float, data_in: Fields) -> Fields:
        """Advance from ``time`` to ``time + dt`` (s) given the partner's fields; return this
        participant's fields at ``time + dt``. Must be repeatable from a restored checkpoint."""

    def store_checkpoint(self) -> Any:
        """A copy of the whole evolving state (restoring it makes a repeated solve identical)."""

    def restore_checkpoint(self, checkpoint: Any) -> None:
        """Put back the state of ``checkpoint``."""
