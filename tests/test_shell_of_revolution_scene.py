"""``fsi run`` of the shell-of-revolution procedure (the bundled ``diaphragm-axisymmetric``
scene on a coarse meridian): what it writes, says and draws, and its keys' checks."""
from __future__ import annotations

import h5py
import numpy as np
import pytest

from fsi.cli import main
from fsi.io.output import read_result
from fsi.scene import SceneError, bundled_scenes, parse_scene
from fsi.slosh.axisymmetric import free_surface_slosh

SMALL = ('[scene]\nname = "axisymmetric"\nprocedure = "shell-of-revolution"\n'
         '[axisymmetric]\nelements = 48\nfills = [0.0, 0.025, 0.05]\nwave_numbers = 12\n'
         'samples = 21\nslosh_fills = [0.05]\n')


def test_the_scene_writes_both_legs_their_stability_and_the_onset(tmp_path, capsys):
    """On 48 elements through tank fractions 0, 0.025 and 0.05 (the Table 4.1 diaphragm,
    the scene's defaults): exit 0; per leg a record per fraction, with the level, the
    stability by wave number (12 harmonics), the meridian's fields at 21 points (the pole on
    the axis, the rim on the tank wall) and units on every dataset; the events are the fill's
    and the drain's snaps and the onset of folding between 0.025 and 0.05 with 9 lobes; the
    n = 1 slosh mode at 0.05 (its lambda1 and slosh mass positive, the hinge inside the tank,
    the free surface's the same as :func:`fsi.slosh.axisymmetric.free_surface_slosh`'s); the
    report prints the tables and the events; four plots."""
    assert "diaphragm-axisymmetric" in bundled_scenes()
    scene = tmp_path / "axi.toml"
    scene.write_text(SMALL)
    assert main(["run", str(scene), "--out", str(tmp_path / "out")]) == 0
    said = capsys.readouterr().out
    assert "fill: folding starts at tank fraction 0.03" in said and "9 lobes" in said
    res = read_result(tmp_path / "out")
    fill, drain = res["axisymmetric_fill"], res["axisymmetric_drain"]
    assert np.allclose(fill["tank_fraction"], [0.0, 0.025, 0.05])
    assert np.allclose(drain["tank_fraction"], [0.0, 0.025, 0.05])
    assert np.asarray(fill["harmonic_eigenvalue"]).shape == (3, 12)
    assert list(fill["stable"]) == [True, True, False]
    assert fill["meridian_radius"].shape == (3, 21) and fill["meridian_stress"].shape == (3, 21, 2)
    assert np.all(fill["meridian_radius"][:, 0] == 0)
    assert np.allclose(fill["meridian_radius"][:, -1], res["attrs"]["radius"])
    events = res["axisymmetric_events"]
    kinds = [e.decode() for e in events["event"]]
    assert kinds == ["fill snaps", "drain snaps", "fill: folding starts"]
    assert 0.025 < events["tank_fraction"][2] < 0.05 and events["lobes"][2] == 9
    with h5py.File(tmp_path / "out" / "result.h5") as f:
        for group in ("axisymmetric_fill", "axisymmetric_drain", "axisymmetric_events"):
            for name, ds in f[group].items():
                assert ds.attrs["units"], f"{group}/{name}"
        assert f["axisymmetric_fill/harmonic_eigenvalue"].attrs["units"] == "1/s^2"
    slosh = res["axisymmetric_slosh"]
    assert np.allclose(slosh["tank_fraction"], [0.05])
    assert slosh["lambda1"][0] > 0 and 0 < slosh["slosh_mass_fraction"][0] < 1
    assert abs(slosh["hinge_height"][0]) < res["attrs"]["radius"]
    assert list(slosh["stable"]) == [False]
    free = free_surface_slosh(0.05, res["attrs"]["radius"], 1000.0, 9.81)
    assert slosh["lambda1_free"][0] == pytest.approx(free.lambda1, rel=1e-12)
    assert "n = 1 slosh on the fill's branch" in said
    with h5py.File(tmp_path / "out" / "result.h5") as f:
        for name, ds in f["axisymmetric_slosh"].items():
            assert ds.attrs["units"], name
        assert f["axisymmetric_slosh/hinge_height"].attrs["units"] == "m"
    assert sorted(p.name for p in (tmp_path / "out" / "plots").iterdir()) == [
        "cross_sections.png", "level_by_fill.png", "slosh_by_fill.png", "stability_map.png"]


@pytest.mark.parametrize("text, key", [
    ("[axisymmetric]\nfills = [0.1, 0.2]\n", "axisymmetric.fills"),
    ("[axisymmetric]\nfills = [0.0, 0.5, 0.4]\n", "axisymmetric.fills"),
    ("[axisymmetric]\nelements = 2\n", "axisymmetric.elements"),
    ("[axisymmetric]\nwall_band = 0.5\n", "axisymmetric.wall_band"),
    ("[axisymmetric]\nwave_numbers = 0\n", "axisymmetric.wave_numbers"),
    ("[axisymmetric]\nslosh_fills = [0.5, 0.3]\n", "axisymmetric.slosh_fills"),
    ("[axisymmetric]\nfills = [0.0, 0.2]\nslosh_fills = [0.1]\n", "axisymmetric.slosh_fills"),
])
def test_bad_axisymmetric_keys_are_named(text, key):
    with pytest.raises(SceneError, match=key.replace(".", r"\.")):
        parse_scene('[scene]\nprocedure = "shell-of-revolution"\n' + text)
