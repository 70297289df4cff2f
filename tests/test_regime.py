"""fsi advise: the dimensionless numbers of a fill, the measured table's interpolation, the
advice and the command.

Oracles: the first slosh period of a half-full rigid sphere from Budiansky's (1960)
lambda_1 = omega_1^2 R / g = 1.5602, which the scene's own (the modes rung on its grid) meets
within its grid's error; the pressures from their definitions (fsi.analysis.regime) with
the bundled diaphragm-fill's numbers worked by hand."""
import numpy as np
import pytest

from fsi.cli import main
from fsi.analysis.regime import FIXED_ADVICE, advise, advise_scene, load_table, predicted, regime
from fsi.scene import load_scene, parse_scene
from fsi.slosh.modal import tank_modes

ROWS = [dict(pressure_ratio=1e-3, eqn_6_1=0.01, level_difference=-2.0, centre_distance_mm=0.01,
             stress_ratio=1.0),
        dict(pressure_ratio=1e-1, eqn_6_1=0.5, level_difference=300.0, centre_distance_mm=0.3,
             stress_ratio=1.5),
        dict(pressure_ratio=1e-2, eqn_6_1=0.1, level_difference=20.0, centre_distance_mm=0.1,
             stress_ratio=1.1)]


def test_regime_of_the_bundled_fill_by_hand():
    r = regime(load_scene("diaphragm-fill"))
    area = np.pi * 0.06**2
    jet = 0.5 * 1000.0 * (5e-4 / area)**2  # 0.977 Pa
    column = 1000.0 * 5e-4 / 0.1 * (0.065 / area + 1 / (np.pi * 0.20955))  # 36.33 Pa
    assert r.dynamic_pressure == pytest.approx(jet + column, rel=1e-12)
    assert r.hydrostatic_pressure == pytest.approx(1000.0 * 9.81 * 0.20955, rel=1e-12)
    # the fill delivers 5e-4 m^3/s ramped over 0.1 s for 0.2 s: 7.5e-5 m^3 on top of half
    assert r.period_fills == pytest.approx((0.5, 0.5 + 7.5e-5 / (4 / 3 * np.pi * 0.20955**3)))
    found = tank_modes(0.20955, 0.5, 16, 1000.0, [0.0, 0.0, -9.81], 2)
    assert r.periods[0] == pytest.approx(2 * np.pi / found.first("lateral").omega, rel=1e-12)
    assert r.slosh_period == max(r.periods)
    # 16^3 cells: lambda1 1.3 % under Budiansky's, the period 0.7 % over
    assert r.slosh_period == pytest.approx(2 * np.pi / np.sqrt(1.5602 * 9.81 / 0.20955),
                                           rel=0.01)
    assert r.time_ratio == pytest.approx(0.2 / r.slosh_period, rel=1e-12)


def test_a_lateral_impulse_adds_rho_a_r():
    scene = load_scene("diaphragm-fill")
    moved = scene.with_keys({"motion": {"kind": "impulse", "amplitude": [2.0, 0.0, 0.0],
                                        "duration": 0.1}})
    extra = regime(moved).dynamic_pressure - regime(scene).dynamic_pressure
    assert extra == pytest.approx(1000.0 * 2.0 * 0.20955, rel=1e-6)


def test_prediction_interpolates_in_log_pi_p_and_never_falls():
    p = predicted(np.sqrt(1e-3 * 1e-2), ROWS)
    assert p["eqn_6_1"] == pytest.approx(0.055) and not p["extrapolated"]
    assert p["stress_ratio"] == pytest.approx(1.05)
    assert predicted(1.0, ROWS)["eqn_6_1"] == 0.5 and predicted(1.0, ROWS)["extrapolated"]
    bumpy = ROWS + [dict(pressure_ratio=3e-2, eqn_6_1=0.05, level_difference=1.0,
                         centre_distance_mm=0.0, stress_ratio=1.0)]
    assert predicted(3e-2, bumpy)["eqn_6_1"] == pytest.approx(0.1)  # the largest so far


def test_advice_follows_the_asked_accuracy_and_gives_its_numbers():
    scene = load_scene("diaphragm-fill")  # Pi_p = 0.018: about 0.11 % by ROWS
    model, lines = advise(scene, 1.0, ROWS)
    assert model == "static" and "0.0181" in lines[0] and "0.27 " in lines[1]
    assert "peak stress x 1.2 " in lines[2]  # 1.1 + 0.4 log10(0.0181 / 0.01)
    assert advise(scene, 0.05, ROWS)[0] == "coupled"
    assert advise_scene(load_scene("slosh-half"), 1.0, ROWS)[0] == FIXED_ADVICE["slosh"][0]
    assert advise_scene(load_scene("thesis-static"), 1.0, ROWS)[0] == "static"


def test_fsi_advise_command(capsys):
    assert len(load_table()) >= 4
    assert main(["advise", "thesis-fill", "--accuracy", "1"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("thesis-fill: ") and "Pi_p" in out and "Eqn 6.1" in out
    assert main(["advise", "thesis-fill", "--accuracy", "-1"]) == 2


def test_advise_says_where_the_diaphragm_starts_to_fold(monkeypatch):
    """``fsi advise`` adds the shell of revolution's onset of folding for a hemispherical
    diaphragm (here on 64 meridian elements: tank fraction 0.039, 9 lobes) and places the
    scene's fills against it: diaphragm-static's 0.1 to 0.7 are all past it; a slosh run at
    0.02 is below it; the full-inversion scale of thesis-static gives no range; the plate and
    the shell of revolution itself are not told."""
    from fsi.analysis import onset

    monkeypatch.setattr(onset, "ELEMENTS", 64)
    monkeypatch.setattr(onset, "FRACTIONS", (0.0, 0.025, 0.05))
    scene = load_scene("diaphragm-static")
    assert onset.fill_range(scene) == (0.1, 0.7)
    assert onset.fill_range(load_scene("thesis-static")) is None
    assert onset.fill_range(load_scene("slosh-half")) == (0.5, 0.5)
    assert not onset.applies(load_scene("thesis-plate"))
    assert not onset.applies(load_scene("diaphragm-axisymmetric"))
    first, second = onset.onset_lines(scene)
    assert "starts to fold at tank fraction 0.03" in first and "9 lobes" in first
    assert "0.1 to 0.7 are all past it" in second
    low = parse_scene('[scene]\nprocedure = "slosh"\n[slosh]\nfill = 0.02\n')
    assert "are below it" in onset.onset_lines(low)[1]
