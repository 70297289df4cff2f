"""Shared fixtures: the thesis material and small models (SI units); reading a script's
module-level constants without importing it.

The suite runs one worker per core (pytest-xdist), so each worker, and every process it
starts, keeps one BLAS thread (unless the environment sets another count): two workers with
a thread per core each wait on each other's cores, which made the suite a third slower on a
fresh clone here (337 s against 245 s)."""
import ast
import os
from pathlib import Path

import pytest
from threadpoolctl import threadpool_limits

for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")
if os.environ["OPENBLAS_NUM_THREADS"] == "1":
    threadpool_limits(1)

from fsi import constants as C
from structure.model import Material, hemisphere_model


@pytest.fixture(scope="session")
def thesis_material():
    return Material(C.MEMBRANE_THICKNESS, C.MEMBRANE_DENSITY, C.MEMBRANE_YOUNGS_MODULUS)


@pytest.fixture(scope="session")
def model26(thesis_material):
    return hemisphere_model(26, C.TANK_RADIUS, thesis_material)


@pytest.fixture(scope="session")
def model10(thesis_material):
    return hemisphere_model(10, C.TANK_RADIUS, thesis_material)


def clamped_disc_under_pressure(n: int, radius: float, pressure: float, law):
    """A flat disc of the App. C disc grid (``n``, ``radius`` m, the thesis thickness), its
    rim held, under ``pressure`` (Pa) along +z at the equilibrium the membrane solver
    finds from a small bulge: (TriangleMembrane, positions (n_nodes, 3) m, rim nodes)."""
    import numpy as np

    from structure.grid import boundary_ring, disc_grid, quad_faces, triangles_from_quads
    from structure.hyperelastic import TriangleMembrane, equilibrium_under_pressure

    points = disc_grid(n, radius)
    triangles = triangles_from_quads(quad_faces(n))
    normal = np.cross(points[triangles[:, 1]] - points[triangles[:, 0]],
                      points[triangles[:, 2]] - points[triangles[:, 0]])[:, 2]
    if normal.mean() < 0:
        triangles = triangles[:, ::-1]
    membrane = TriangleMembrane(points, triangles, C.MEMBRANE_THICKNESS)
    start = points.copy()
    start[:, 2] = 1e-3 * (1 - (np.hypot(points[:, 0], points[:, 1]) / radius) ** 2)
    fixed = boundary_ring(n, 0)
    return membrane, equilibrium_under_pressure(membrane, law, pressure, fixed, start), fixed


TINY_RAMP = """
[scene]
name = "small-ramp"
procedure = "thesis-ramp"
[membrane]
grid_size = 8
[thesis]
end_time = 0.05
frame_interval = 50
[sweep]
fills = [0.0, 0.5, 1.0]
"""
"""The thesis ramp small enough for seconds: N = 8, 500 steps, three frames by volume."""

TINY_SWEEP = ("[scene]\nname = 'tiny'\nprocedure = 'volume-sweep'\n[membrane]\n"
              "grid_size = 8\n[structure]\nmodel = 'xpbd'\n[sweep]\nscale = 'tank'\n"
              "fills = [0.1, 0.2]\ndrain = true\n")
"""A static sweep small enough for seconds: N = 8, XPBD, two tank fractions and the drain."""


@pytest.fixture
def tiny_sweep_scene(tmp_path):
    """The path of :data:`TINY_SWEEP` written as a scene file."""
    scene = tmp_path / "sweep.toml"
    scene.write_text(TINY_SWEEP)
    return scene


def module_constant(path: Path, name: str):
    """The literal value of the module-level assignment ``name = ...`` in ``path`` (read
    without importing the script), or None."""
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if isinstance(node, ast.Assign) and any(
                isinstance(target, ast.Name) and target.id == name for target in node.targets):
            try:
                return ast.literal_eval(node.value)
            except ValueError:
                pytest.fail(f"{path.name}: {name} must be a literal, e.g. ('key', ...)")
    return None
