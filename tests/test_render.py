"""The 3-D renders of the diaphragm (:mod:`fsi.io.render`): a frame of a tiny static sweep
renders off screen with its colourbar, the liquid lies on the right side of the sheet, and
without a renderer the 3-D plots are skipped in one line while the others are made."""
import logging
import os
import shutil
import signal
import sys

import numpy as np
import pytest
from conftest import TINY_SWEEP

from fsi.cli import main
from fsi.io import render
from fsi.io.output import read_result
from fsi.io.plots import make_plots
from structure.grid import disc_grid, quad_faces, triangles_from_quads


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    """The folder of :data:`TINY_SWEEP` run without plots (N = 8, two tank fractions)."""
    folder = tmp_path_factory.mktemp("tiny")
    scene = folder / "sweep.toml"
    scene.write_text(TINY_SWEEP)
    assert main(["run", str(scene), "--out", str(folder / "run"), "--no-plots"]) == 0
    return folder / "run"


@pytest.fixture
def renderer():
    """Skips where no off-screen renderer opens, unless RENDER_REQUIRED=1 (CI, which installs
    Mesa's EGL: there the render must be made)."""
    ok, reason = render.renderer_available()
    if not ok:
        if os.environ.get("RENDER_REQUIRED") == "1":
            pytest.fail(f"RENDER_REQUIRED=1 but no renderer opens: {reason}")
        pytest.skip(f"no renderer here: {reason}")


def test_the_liquid_is_below_the_sheet_and_above_it_once_the_sheet_folds_over():
    """A flat sheet at z = 0: a point under it is on the liquid's side, one over it on the
    gas's, each by its vertical distance; a second layer above (a fold) turns the side."""
    radius = 0.2
    points = disc_grid(8, radius)
    tri = triangles_from_quads(quad_faces(8))
    probe = np.array([[0.01, 0.02, -0.05], [0.01, 0.02, 0.03]])
    assert render.sheet_side(points, tri, probe) == pytest.approx([-0.05, 0.03])
    folded = np.vstack([points, points + [0.0, 0.0, 0.1]])
    assert render.sheet_side(folded, np.vstack([tri, tri + len(points)]), probe) == \
        pytest.approx([0.05, -0.03])


def test_a_peak_under_a_fold_is_seen_from_where_the_sheet_does_not_hide_it():
    """A flat sheet at z = 0 over a small patch at z = -0.05: the patch's centre is hidden
    from above, so the camera chosen for it looks from below the sheet."""
    radius = 0.2
    top, patch = disc_grid(8, radius), disc_grid(4, 0.02) + [0.0, 0.0, -0.05]
    tri = np.vstack([triangles_from_quads(quad_faces(8)),
                     triangles_from_quads(quad_faces(4)) + len(top)])
    position = np.vstack([top, patch])
    frame = render.Frame(position, position, tri, np.ones(len(tri), bool), {}, radius)
    point = patch[[5, 6, 9, 10]].mean(axis=0)
    assert render.hidden(frame, point, np.array([0.0, 0.0, 1.0]))
    assert not render.hidden(frame, point, np.array([0.0, 0.0, -1.0]))
    camera = render.camera_seeing(frame, point)
    assert camera.elevation_deg < 0
    assert not render.hidden(frame, point, np.asarray(camera.position(radius)[0]))


def test_a_frame_renders_with_its_colourbar_tank_and_liquid(tiny_run, renderer):
    res = read_result(tiny_run)
    frame = render.frame_of(res, "frames", 1)
    view = render.View(frame, "von_mises", render.percentile_scale(
        render.sheet_values(frame, "von_mises")), title="tank fraction 0.2")
    with render.Renderer((450, 350)) as r:
        image = r.image(view).astype(float)
    height, width, _ = image.shape
    assert (height, width) == (350, 450)
    assert image.std() > 20
    assert len(np.unique(image.reshape(-1, 3), axis=0)) > 300
    bar = image[int(0.25 * height):int(0.78 * height), int(0.875 * width):int(0.895 * width)]
    assert bar.std(axis=0).max() > 20                     # the colourbar's colours run
    blue = (image[..., 2] > image[..., 0] + 30) & (image[..., 2] > 120)
    assert blue.sum() > 500                                # the wetted wall


def test_make_plots_writes_the_3d_renders(tiny_run, renderer, tmp_path):
    run = shutil.copytree(tiny_run, tmp_path / "run")
    names = {p.name for p in make_plots(run)}
    assert {"surface_tank_010.0.png", "surface_tank_020.0.png",
            "peak_stress_frame.png"} <= names


def test_without_a_renderer_the_3d_plots_are_skipped_in_one_line(tiny_run, tmp_path,
                                                                 monkeypatch, caplog):
    monkeypatch.setattr(render, "renderer_available", lambda: (False, "no window in a test"))
    monkeypatch.setattr(render, "_REPORTED", set())
    run = shutil.copytree(tiny_run, tmp_path / "run")
    with caplog.at_level(logging.WARNING):
        names = {p.name for p in make_plots(run)}
    said = [r.getMessage() for r in caplog.records if "3-D plots skipped" in r.getMessage()]
    assert said == ["3-D plots skipped: no window in a test"]
    assert not [n for n in names if n.startswith("surface_") or n == "peak_stress_frame.png"]
    assert {"cross_sections.png", "stress_envelope.png", "diaphragm_history.png"} <= names


def test_a_missing_pyvista_is_a_reason_not_an_error(monkeypatch):
    monkeypatch.setitem(sys.modules, "pyvista", None)
    ok, reason = render.renderer_available.__wrapped__()
    assert not ok and reason.startswith("pyvista cannot be imported")


def test_a_render_window_that_stops_its_process_is_a_reason_not_a_crash(monkeypatch):
    """VTK stops a process whose window cannot be made (an X window without a display):
    the window is tried in a child process."""
    monkeypatch.setattr(render, "WINDOW_PROBE",
                        "import os, signal; os.kill(os.getpid(), signal.SIGSEGV)")
    assert render.renderer_available.__wrapped__() == (
        False, f"no off-screen render window (VTK stopped by signal {signal.SIGSEGV.value})")
