"""Grid locking of the thesis particle membrane: strain limit x grid size.

Levine (2014) Sec. 4.2.5 (thesis text lines 4613-4629): "for low resolution grids a phenomenon
called "grid locking" can occur in which the bent elements cannot deform enough to invert,
causing the grid to lock into place, artificially stopping the solution. Allowable strain
levels less than 2% were observed to be particularly susceptible to grid locking." This
case measures exactly that: whether the thesis stepper (:func:`structure.thesis.step`,
explicit Euler, App. G strain limiting with the thesis's ErrorLimit, App. H bend limiting, fixed two-ring rim, courant-drag damping, as the
bundled ``thesis-ramp`` scene) stops before the membrane has inverted.

For each grid size N and strain limit (ErrorLimit, %), the thesis-ramp scene at that N and limit
is run as :func:`fsi.procedures.thesis_ramp` runs it (equivalent fluid height ramped linearly
from -1.05 R to +1.05 R, the height updated before each step), over ``--end-time`` seconds
instead of the thesis's 5 s, then held at +1.05 R for up to ``--hold`` seconds until the
membrane has stopped (the liquid volume changes by less than SETTLE_TOL of the mirrored volume
over SETTLE_WINDOW s). The hold separates locking (the solution stops) from lag (the ramp was
too fast for the membrane to follow). The full-inversion static solve that ``thesis_ramp`` also
makes is skipped: the fill here is on the geometric scale, not on the project's fill scale.

Measured per point:

- inverted_fraction (-): fill on the geometric scale :meth:`structure.volume.FillScale.mirrored`,
  (V - V_rest) / (V_mirrored - V_rest), V the liquid volume (m^3) at the end of the hold
  (``ramp_end_fraction``: the same at the end of the ramp). 1 = the rest shape mirrored through
  the equator. The clamped band (second fixed ring, a cell below the equator) cannot invert, so
  even a converged inversion holds less: ``static_cap`` is the fill of the fully inverted static
  equilibrium (:func:`fsi.setup.fill.full_inversion`, independent of the limit), one per grid.
- strain_mean (-): Sum |L - L0| / Sum L0 over the in-plane springs at the end (the thesis's
  error, measured after all constraints); strain_max (-): largest single spring |L - L0| / L0.
- seconds (s): wall time of the point (ramp + hold, compiled kernels).
- status: ``inverted``, ``locked`` (see LOCK_RATIO), ``courant-error`` (the stepper raised
  :class:`structure.thesis.CourantError`: a failed point, fraction at the last good step).

Locked: a point is locked when, at the end, it holds less than LOCK_RATIO of what the
reference point reaches, the reference being the finest grid at the loosest limit, after both are
divided by their grid's static cap (so the unavoidable clamped band, which shrinks as 1/N, does
not count as locking): locked <=> (f / cap_N) < LOCK_RATIO * (f_ref / cap_ref). Measured with
the defaults, every point that inverts reaches >= 0.88 of the reference and every locked point
<= 0.73 of it (most < 0.5); 0.8 sits in that gap.
"""
from __future__ import annotations

import time

import numpy as np

from fsi.setup.build import build
from fsi.setup.fill import full_inversion
from fsi.setup.models import hydrostatic_load
from fsi.procedures.thesis_ramp import thesis_settings
from fsi.scene import SceneError, parse_scene
from structure.statics import strain_error
from structure.thesis import CourantError, ThesisState, step
from structure.volume import FillScale, liquid_volume

LOCK_RATIO = 0.8
"""Locked below this fraction of the reference's cap-normalised fill (see module docstring)."""
SETTLE_WINDOW = 0.05
"""s: the hold stops when the volume moved less than SETTLE_TOL over this window."""
SETTLE_TOL = 1e-4
"""Volume change over SETTLE_WINDOW, as a fraction of V_mirrored - V_rest, that counts as
stopped."""


def scene_for(grid_size: int, error_limit: float, end_time: float, dt: float):
    """The bundled thesis-ramp scene at another grid size, strain limit (%), ramp time (s), dt."""
    return build(parse_scene(
        f"[scene]\nprocedure = 'thesis-ramp'\n[membrane]\ngrid_size = {grid_size}\n"
        f"[constraints]\nerror_limit = {error_limit!r}\nbend_limit_iterations = 10\n"
        f"[thesis]\ndt = {dt!r}\nend_time = {end_time!r}\n"))


def static_cap(grid_size: int) -> float:
    """Fill (geometric scale) of the fully inverted static equilibrium at N (limit 1 %)."""
    setup = build(parse_scene(f"[scene]\nprocedure = 'volume-sweep'\n[membrane]\n"
                              f"grid_size = {grid_size}\n"))
    full = full_inversion(setup)
    return float(FillScale.mirrored(setup.model).fill(full.info.liquid_volume))


def run_point(grid_size: int, error_limit: float, end_time: float, hold: float,
              dt: float) -> dict:
    """Ramp (as thesis_ramp) then hold at the final height until stopped; see module docstring."""
    try:
        setup = scene_for(grid_size, error_limit, end_time, dt)
    except SceneError as exc:  # dt above the a-priori Courant limit (fsi.setup.build)
        return {"grid_size": grid_size, "error_limit": error_limit, "inverted_fraction": np.nan,
                "strain_mean": np.nan, "seconds": 0.0, "status": "courant-error",
                "ramp_end_fraction": np.nan, "strain_max": np.nan, "ramp_time": end_time,
                "hold_time": 0.0, "settled": False, "dt": dt, "steps": 0, "message": str(exc)}
    model, liquid, th = setup.model, setup.liquid, setup.scene["thesis"]
    settings = thesis_settings(setup)
    scale = FillScale.mirrored(model)
    n_ramp = int(round(th["end_time"] / th["dt"]))
    n_hold = int(round(hold / dt))
    window = max(1, int(round(SETTLE_WINDOW / dt)))
    h0, h1 = th["height_start"] * model.radius, th["height_end"] * model.radius
    state = ThesisState(model.node_rest_position)
    status, message = "ok", ""
    ramp_end = np.nan
    held = 0
    settled = False
    tic = time.perf_counter()
    last_fill = scale.fill(liquid_volume(model, state.node_position))
    try:
        for k in range(1, n_ramp + n_hold + 1):
            h = h0 + (h1 - h0) * min(k, n_ramp) / n_ramp
            level = liquid.reference_pressure(h)
            state, _ = step(model, state, hydrostatic_load(liquid, pressure_level=level),
                            th["dt"], settings)
            if k == n_ramp:
                ramp_end = float(scale.fill(liquid_volume(model, state.node_position)))
            if k > n_ramp:
                held = k - n_ramp
                if held % window == 0:
                    fill = float(scale.fill(liquid_volume(model, state.node_position)))
                    if abs(fill - last_fill) < SETTLE_TOL:
                        settled = True
                        break
                    last_fill = fill
            elif k == n_ramp:
                last_fill = ramp_end
    except CourantError as exc:
        status, message = "courant-error", str(exc)
    seconds = time.perf_counter() - tic
    pos = state.node_position
    mean, worst = strain_error(model, pos)
    return {"grid_size": grid_size, "error_limit": error_limit,
            "inverted_fraction": float(scale.fill(liquid_volume(model, pos))),
            "strain_mean": mean, "seconds": seconds, "status": status,
            "ramp_end_fraction": ramp_end, "strain_max": worst, "ramp_time": end_time,
            "hold_time": held * dt, "settled": settled, "dt": dt,
            "steps": n_ramp + held, "message": message}


def locked(row: dict, reference_norm: float) -> bool:
    """True when ``row`` holds less than LOCK_RATIO of the reference (both cap-normalised)."""
    return row["inverted_fraction"] / row["static_cap"] < LOCK_RATIO * reference_norm


def classify(rows: list[dict], caps: dict) -> dict:
    """Set each row's static cap, cap-normalised fill and status (``inverted``/``locked``;
    ``courant-error`` kept); the reference is the finest grid at the loosest limit of ``rows``.
    Rows carrying a ``fraction_2x`` (the run at twice the ramp time) also get ``status_2x``.
    Returns the reference."""
    for r in rows:
        r["static_cap"] = caps[r["grid_size"]]
        r["cap_normalised"] = r["inverted_fraction"] / r["static_cap"]
    ok = [r for r in rows if r["status"] != "courant-error"]
    finest = max(r["grid_size"] for r in ok)
    loosest = max(r["error_limit"] for r in ok if r["grid_size"] == finest)
    ref = next(r for r in ok if r["grid_size"] == finest and r["error_limit"] == loosest)
    ref_norm = ref["cap_normalised"]
    for r in rows:
        if r["status"] != "courant-error":
            r["status"] = "locked" if locked(r, ref_norm) else "inverted"
        if "fraction_2x" in r and r.get("status_2x") != "courant-error":
            r["status_2x"] = "locked" if locked(
                dict(r, inverted_fraction=r["fraction_2x"]), ref_norm) else "inverted"
    return {"grid_size": finest, "error_limit": loosest,
            "inverted_fraction": ref["inverted_fraction"], "cap_normalised": ref_norm,
            "lock_threshold_cap_normalised": LOCK_RATIO * ref_norm}
