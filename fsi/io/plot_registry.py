"""The registry of result plots: procedure name -> the function that draws its results
(:mod:`fsi.io.plots`, :mod:`fsi.io.modes_plots`), and the one way a figure is saved."""
from __future__ import annotations

from pathlib import Path
from typing import Callable

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PLOTS: dict[str, Callable[[dict, Path], list[Path]]] = {}
"""procedure name -> plots(result, folder) -> written paths; procedures not listed get the
membrane plots (:func:`fsi.io.plots.membrane_plots`)."""


def register_plots(procedure: str):
    """Decorator: ``plots(result, folder)`` draws the results of ``procedure``."""
    def add(plots):
        PLOTS[procedure] = plots
        return plots
    return add


def save(fig, path: Path) -> Path:
    """Write ``fig`` to ``path`` (PNG, 90 dpi) and close it."""
    fig.savefig(path, dpi=90, bbox_inches="tight")
    plt.close(fig)
    return path
