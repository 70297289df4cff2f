"""Where a scene's hemispherical diaphragm starts to fold, from the shell of revolution
(:mod:`structure.axisymmetric`), and whether the scene's fills are past it: what
``fsi advise`` adds for a scene whose 3-D sheet may fold.

The scene's hemisphere (its tank radius, membrane and liquid, with the full law: the
harmonics' second variation needs it) on :data:`ELEMENTS` meridian elements
(:func:`fsi.procedures.shell_of_revolution.build`) is filled from rest through
:data:`FRACTIONS`; the onset of folding is where the axisymmetric branch first loses its
stability to a circumferential harmonic (:func:`structure.axisymmetric.folding.onset_of_folding`).
On the Table 4.1 diaphragm this grid gives the onset within 0.1 % of the 384-element value
(``docs/data/diaphragm_axisymmetric.json``).
"""
from __future__ import annotations

from typing import Optional

import numpy as np

from fsi.analysis.regime import end_fill

ELEMENTS = 128
"""Meridian elements of the onset's computation."""
FRACTIONS = tuple(float(f) for f in np.round(np.arange(0.0, 0.2001, 0.025), 4))
"""The tank fractions the fill passes through to find the onset (none found: it is beyond)."""
SECONDS = 10.0
"""About how long the computation takes here (two cores)."""


def fill_range(scene) -> Optional[tuple[float, float]]:
    """(lowest, highest) tank fraction the scene holds where it says so on the tank's scale
    (a coupled fill's start and end, a static sweep's fills on the tank scale, a slosh run's
    fill); None otherwise."""
    procedure = scene["scene"]["procedure"]
    if procedure == "coupled-fill":
        ends = (scene["dynamics"]["start_fill"], end_fill(scene))
    elif procedure == "volume-sweep" and scene["sweep"]["scale"] == "tank":
        ends = tuple(scene["sweep"]["fills"])
    elif procedure == "slosh":
        ends = (scene["slosh"]["fill"],)
    else:
        return None
    return float(min(ends)), float(max(ends))


def applies(scene) -> bool:
    """Whether the scene has a hemispherical diaphragm whose folding the onset tells of."""
    return scene["membrane"]["shape"] == "hemisphere" and \
        scene["scene"]["procedure"] not in ("plate-estimate", "shell-of-revolution")


def folding_onset(scene):
    """The onset of folding (:class:`structure.axisymmetric.folding.Onset`) of the scene's
    diaphragm filled from rest (module doc), or None where none is met by the last of
    :data:`FRACTIONS`."""
    from fsi.setup.shell_of_revolution import build
    from structure.axisymmetric.study import fill_onset

    shell, load = build(scene, ELEMENTS, wrinkling="none")
    return fill_onset(shell, load, FRACTIONS)


def onset_lines(scene) -> list[str]:
    """What ``fsi advise`` says of the onset (module doc): where the sheet starts to fold and
    with how many lobes, and whether the scene's fills are past it."""
    if not applies(scene):
        return []
    onset = folding_onset(scene)
    if onset is None:
        return [f"the shell of revolution ({ELEMENTS} meridian elements) stays axisymmetric "
                f"up to tank fraction {FRACTIONS[-1]:g} filling from rest"]
    at = f"at tank fraction {onset.tank_fraction:.4f}" if onset.resolved else \
        f"between tank fractions {onset.bracket[0]:.3f} and {onset.bracket[1]:.3f}"
    lines = [f"the diaphragm starts to fold {at}, with {onset.lobes} lobes (the shell of "
             f"revolution on {ELEMENTS} meridian elements, filling from rest; "
             "docs/models/shell-of-revolution.md)"]
    span = fill_range(scene)
    if span is not None:
        low, high = span
        if low > onset.tank_fraction:
            lines.append(f"this scene's tank fractions {low:.3g} to {high:.3g} are all past it: "
                         "its 3-D sheet folds, so its shapes and stresses depend on the "
                         "membrane grid (docs/notes/axisymmetric-onset-vs-3d.md)")
        elif high > onset.tank_fraction:
            lines.append(f"this scene's tank fractions {low:.3g} to {high:.3g} cross it")
        else:
            lines.append(f"this scene's tank fractions {low:.3g} to {high:.3g} are below it: "
                         "its sheet stays axisymmetric")
    return lines
