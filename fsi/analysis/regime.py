"""Which model a coupled scene needs: the two dimensionless numbers of a fill or drain through
the port, and the measured static-against-dynamic differences they predict::

    Pi_p = p_dyn / (rho g R)               dynamic over hydrostatic pressure
    p_dyn = rho u^2 / 2                    the port jet, u = Q / (pi r_p^2)
          + rho (dQ/dt) (L_p / (pi r_p^2) + 1 / (pi R))
                                           the liquid accelerated through the stub and
                                           into the tank, dQ/dt = Q / ramp_time
          + rho a_lat R                    the tank's largest lateral acceleration
    Pi_t = T_fill / T_1                    the fill's duration over the first slosh period,
    T_1  = 2 pi / omega_1                  the scene's own: the first lateral mode of its
                                           liquid at its start and end tank fractions
                                           (the modes rung, :func:`fsi.slosh.modal.tank_modes`,
                                           on the scene's fluid grid), the longer of the two

with Q = ``port.flow``, r_p and L_p the port stub's radius and length, T_fill =
``dynamics.end_time``, g = |``liquid.body_acceleration``|.  Small Pi_p: the pressure the
flow adds is small against the hydrostatic one and the static model holds; the measured
table (:data:`REGIME_TABLE_FILE`, written by ``benchmarks/static_vs_dynamic.py
--write-table``) gives the static-against-dynamic difference (Eqn 6.1, pressure level,
centre of mass) that runs at known Pi_p showed, and :func:`advise` interpolates it in
log Pi_p (beyond the measured range: the nearest end, said so).
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from fsi.setup.motion import tank_acceleration
from fsi.slosh.modal import tank_modes
from fsi.text import about
from structure.volume import tank_volume

REGIME_TABLE_FILE = Path(__file__).with_name("regime_table.json")
LATERAL_SAMPLES = 2001
"""Samples of a(t) over the run for its largest lateral value (-)."""
PERIOD_FILLS = (0.05, 0.95)
"""The tank fractions within which the slosh period is computed (a fill's ends clipped)."""


@dataclass(frozen=True)
class Regime:
    """The dimensionless numbers of a scene and the pressures behind them (Pa, s)."""

    dynamic_pressure: float
    hydrostatic_pressure: float
    fill_time: float
    slosh_period: float
    period_fills: tuple = ()
    periods: tuple = ()

    @property
    def pressure_ratio(self) -> float:
        """Pi_p = p_dyn / (rho g R) (-)."""
        return self.dynamic_pressure / self.hydrostatic_pressure

    @property
    def time_ratio(self) -> float:
        """Pi_t = T_fill / T_1 (-)."""
        return self.fill_time / self.slosh_period


def regime(scene) -> Regime:
    """:class:`Regime` of a coupled-fill scene (module doc)."""
    rho = scene["liquid"]["density"]
    g = float(np.linalg.norm(scene["liquid"]["body_acceleration"]))
    radius = scene["tank"]["radius"]
    port, dyn = scene["port"], scene["dynamics"]
    area = np.pi * port["radius"]**2
    flow = abs(port["flow"])
    jet = 0.5 * rho * (flow / area)**2
    column = rho * flow / port["ramp_time"] * (port["length"] / area + 1.0 / (np.pi * radius))
    times = np.linspace(0.0, dyn["end_time"], LATERAL_SAMPLES)
    a = tank_acceleration(scene["motion"])
    lateral = max(float(np.hypot(*a(t)[:2])) for t in times)
    fills, periods = slosh_periods(scene)
    return Regime(dynamic_pressure=jet + column + rho * lateral * radius,
                  hydrostatic_pressure=rho * g * radius, fill_time=dyn["end_time"],
                  slosh_period=max(periods), period_fills=fills, periods=periods)


def end_fill(scene) -> float:
    """The tank fraction at a coupled fill's end: the start's plus the volume the port's
    ramped flow Q(t) = flow min(t / ramp_time, 1) delivers by ``dynamics.end_time``."""
    port, dyn = scene["port"], scene["dynamics"]
    end, ramp = dyn["end_time"], port["ramp_time"]
    delivered = port["flow"] * (end * end / (2 * ramp) if end <= ramp else end - ramp / 2)
    return dyn["start_fill"] + delivered / tank_volume(scene["tank"]["radius"])


def period_fills(scene) -> tuple[float, float]:
    """The (start, end) tank fractions of a coupled fill at which :func:`slosh_periods`
    computes the slosh period, clipped to :data:`PERIOD_FILLS`."""
    return tuple(float(np.clip(f, *PERIOD_FILLS))
                 for f in (scene["dynamics"]["start_fill"], end_fill(scene)))


def slosh_periods(scene) -> tuple[tuple, tuple]:
    """((start, end) tank fractions, their first lateral slosh periods (s)): the modes rung
    on the scene's fluid grid (:func:`fsi.slosh.modal.tank_modes`), the fractions clipped
    to :data:`PERIOD_FILLS`."""
    fills = period_fills(scene)
    periods = []
    for fill in fills:
        found = tank_modes(scene["tank"]["radius"], fill, scene["fluid"]["cells"],
                           scene["liquid"]["density"], scene["liquid"]["body_acceleration"], 2)
        periods.append(2 * np.pi / found.first("lateral").omega)
    return fills, tuple(periods)


def load_table(path: Path = REGIME_TABLE_FILE) -> list[dict]:
    """The measured rows: pressure_ratio, time_ratio, eqn_6_1 (%), level_difference (Pa),
    centre_distance_mm, stress_ratio (the dynamic amplification of the sheet's peak
    stress), and the run's name and flow."""
    return json.loads(Path(path).read_text())["runs"]


PREDICTED = ("eqn_6_1", "level_difference", "centre_distance_mm", "stress_ratio")
"""The measures :func:`predicted` interpolates between the table's runs."""


def predicted(pressure_ratio: float, rows: list[dict]) -> dict:
    """The static-against-dynamic differences at ``pressure_ratio``: each measure of
    :data:`PREDICTED` that every row has interpolated in log Pi_p through the measured runs sorted by Pi_p (the largest so far,
    so the prediction never falls as Pi_p grows), and ``extrapolated`` when outside them."""
    rows = sorted(rows, key=lambda r: r["pressure_ratio"])
    x = np.log10([r["pressure_ratio"] for r in rows])
    out = {}
    for key in (k for k in PREDICTED if all(k in r for r in rows)):
        y = np.maximum.accumulate(np.abs([r[key] for r in rows]))
        out[key] = float(np.interp(np.log10(pressure_ratio), x, y))
    out["extrapolated"] = not x[0] <= np.log10(pressure_ratio) <= x[-1]
    return out


def advise(scene, accuracy: float, rows: list[dict]) -> tuple[str, list[str]]:
    """(model, reasons): 'static' when the predicted Eqn 6.1 difference between the coupled
    run and the static model is within ``accuracy`` (%), else 'coupled'; the reasons give
    every number used."""
    r = regime(scene)
    p = predicted(r.pressure_ratio, rows)
    lines = [f"Pi_p = p_dyn / (rho g R) = {r.dynamic_pressure:.4g} Pa / "
             f"{r.hydrostatic_pressure:.4g} Pa = {r.pressure_ratio:.3g}",
             f"Pi_t = T_fill / T_1 = {r.fill_time:.4g} s / {r.slosh_period:.3g} s = "
             f"{r.time_ratio:.3g} (T_1 the first lateral slosh period of the scene's liquid: "
             + ", ".join(f"{t:.3g} s at tank fraction {f:.3g}"
                         for f, t in zip(r.period_fills, r.periods))
             + ", the linear modes on its fluid grid)",
             f"measured static-against-dynamic difference at this Pi_p "
             f"({'beyond the measured range: its nearest end' if p['extrapolated'] else 'interpolated'}"
             f", {len(rows)} runs): Eqn 6.1 {p['eqn_6_1']:.3g} %, pressure level "
             f"{p['level_difference']:.3g} Pa, centre of mass {p['centre_distance_mm']:.3g} mm"
             + (f", peak stress x {p['stress_ratio']:.3g} of the static model's (the dynamic "
                "amplification)" if "stress_ratio" in p else "")]
    model = "static" if p["eqn_6_1"] <= accuracy else "coupled"
    lines.append(f"asked accuracy {accuracy:g} % Eqn 6.1: "
                 + ("the static (hydrostatic) model is enough" if model == "static" else
                    "the coupled dynamic model is needed"))
    return model, lines


FIXED_ADVICE = {
    "plate-estimate": ("analytical", "a flat diaphragm's closed forms (thesis Ch. 3), each "
                       "with its validity range in w0/t; beyond it, the static sweep"),
    "volume-sweep": ("static", "fills held at rest: no flow and no tank motion, so the "
                     "hydrostatic load is exact and the static sweep is the model"),
    "thesis-ramp": ("static", "the thesis's quasi-static ramp: the hydrostatic model by "
                    "construction"),
    "slosh": ("coupled", "a slosh mode's frequency, damping and forces need the liquid's "
              "inertia: only the coupled dynamic model has it"),
    "shell-of-revolution": ("axisymmetric", "the diaphragm's axisymmetric branch, its snaps "
                            "and its stability to each circumferential wave number, converged "
                            "in the meridian grid; past the onset of folding it reports where "
                            "the sheet folds and with how many lobes, and the folded shape "
                            "needs the 3-D sheet"),
}
"""Procedures whose model follows from what they compute, with the reason."""


PERIOD_SECONDS = 1.2
"""Wall seconds of one slosh period of :func:`slosh_periods` (an eigenvalue problem,
:func:`fsi.slosh.modal.tank_modes`) on a :data:`PERIOD_CELLS`-cell fluid grid, measured on two
cores: 0.02 s at 16 cells, 0.2 s at 24, 16 s at 48, 93 s at 64."""
PERIOD_CELLS = 32
PERIOD_COST_EXPONENT = 6.3
"""The slosh period's cost grows as fluid.cells to this power (the fit of the times above)."""
COMPILE_SECONDS = 20.0
"""What a first run adds, compiling the fluid grid's cut-cell kernels (numba caches them)."""


def work_seconds(scene) -> float:
    """Rough wall seconds of :func:`advise` on ``scene`` once compiled: its two slosh
    periods (the rest takes milliseconds)."""
    cells = scene["fluid"]["cells"]
    return 2 * PERIOD_SECONDS * (cells / PERIOD_CELLS) ** PERIOD_COST_EXPONENT


def work_note(scene) -> str:
    """What :func:`advise_scene` computes for ``scene`` and roughly how long it takes, to say
    before it starts; '' when its answer is a fixed one (FIXED_ADVICE: nothing computed)."""
    if scene["scene"]["procedure"] in FIXED_ADVICE:
        return ""
    start, end = period_fills(scene)
    return (f"computing the liquid's first slosh period at tank fractions {start:.3g} and "
            f"{end:.3g} on its {scene['fluid']['cells']}-cell fluid grid "
            f"({about(work_seconds(scene))}; {COMPILE_SECONDS:.0f} s more on a first run, "
            f"while the fluid kernels compile)")


def advise_scene(scene, accuracy: float, rows: list[dict]) -> tuple[str, list[str]]:
    """(model, reasons) for any scene: the measured regime (:func:`advise`) for a fill or
    drain, the fixed answer of FIXED_ADVICE otherwise."""
    procedure = scene["scene"]["procedure"]
    if procedure in FIXED_ADVICE:
        model, reason = FIXED_ADVICE[procedure]
        return model, [f"procedure {procedure}: {reason}"]
    return advise(scene, accuracy, rows)


def plot_map(rows: list[dict]):
    """The regime map: each measured run at (Pi_t, Pi_p), coloured and labelled by its
    largest Eqn 6.1 difference from the static equilibrium; ``rows`` as :func:`load_table`'s. A
    matplotlib Figure."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    points = ax.scatter([r["time_ratio"] for r in rows], [r["pressure_ratio"] for r in rows],
                        c=[max(r["eqn_6_1"], 1e-6) for r in rows], norm=LogNorm(),
                        cmap="viridis", s=60)
    for r in rows:
        ax.annotate(f"{r['name']}\n{r['eqn_6_1']:.2g} %", (r["time_ratio"], r["pressure_ratio"]),
                    fontsize=7, xytext=(4, 4), textcoords="offset points")
    fig.colorbar(points, label="largest Eqn 6.1 against the static equilibrium (%)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("Pi_t = fill time / first slosh period")
    ax.set_ylabel("Pi_p = dynamic / hydrostatic pressure")
    ax.set_title("Regime map: coupled fill against the static model")
    ax.grid(alpha=0.3, which="both")
    return fig
