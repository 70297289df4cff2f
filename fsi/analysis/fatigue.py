"""Stress cycles of the most loaded triangles and their fatigue damage.

The stress history of a triangle is its ``surface_stress`` over the frames of a run in time
(Pa). :func:`stress_cycles` rainflow-counts it (ASTM E1049-85, through the ``rainflow``
package) for the ``fatigue.peak_triangles`` triangles of the free sheet of largest envelope
stress: each row a range (Pa), its mean (Pa) and its count (0.5 for a half cycle). The
frames sample the history at the scene's frame interval, so ranges between frames are not
seen: a frame interval of a tenth of the forcing's period or less is the scene's to choose.

With an S-N curve in the scene (``fatigue.sn_curve``: points [stress range Pa, cycles to
failure], range falling as cycles grow), :func:`miner_damage` sums Palmgren-Miner's
n_i / N(S_i) per triangle, N(S) interpolated log-log between the points and extended along the
end segments above the first point; ranges below the last point's do no damage (the curve's
end is its endurance limit). The damage is per run of the scene (one forced-slosh record, one
fill-drain cycle). No curve is assumed for any material: without one there is no damage.
"""
from __future__ import annotations

import numpy as np
import rainflow


def stress_cycles(history: np.ndarray) -> np.ndarray:
    """(c, 3): the rainflow cycles (range Pa, mean Pa, count) of ``history`` (f,) Pa."""
    rows = [(r, m, c) for r, m, c, _, _ in rainflow.extract_cycles(np.asarray(history, float))]
    return np.asarray(rows, dtype=float).reshape(-1, 3)


def cycles_to_failure(sn_curve, stress_range: np.ndarray) -> np.ndarray:
    """N(S) (module doc) of ranges ``stress_range`` (Pa) on ``sn_curve`` ((k, 2): range Pa,
    cycles); inf below the last point's range."""
    curve = np.asarray(sn_curve, dtype=float)
    s, n = np.log(curve[::-1, 0]), np.log(curve[::-1, 1])   # range ascending
    x = np.log(np.maximum(np.asarray(stress_range, dtype=float), np.finfo(float).tiny))
    inside = np.interp(x, s, n)
    above = n[-1] + (x - s[-1]) * (n[-1] - n[-2]) / (s[-1] - s[-2])
    out = np.exp(np.where(x > s[-1], above, inside))
    return np.where(x < s[0], np.inf, out)


def miner_damage(cycles: np.ndarray, sn_curve) -> float:
    """Palmgren-Miner's sum of count / N(range) over ``cycles`` (:func:`stress_cycles`)."""
    if len(cycles) == 0:
        return 0.0
    return float(np.sum(cycles[:, 2] / cycles_to_failure(sn_curve, cycles[:, 0])))
