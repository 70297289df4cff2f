"""The spring-mass equivalent of each slosh mode of an eigenvalue analysis
(:func:`fluid.modes.surface_modes`): the same quantities, names and units as the time
domain's :class:`fsi.slosh.analysis.MechanicalModel`, read from the mode shapes instead of a
force record.

For a mode j with surface elevation eta_j (normalised to sum rho A eta^2 = 1 kg) and
displacement field xi_j in the liquid, excited by a lateral tank acceleration a along x
(NASA SP-106, ch. 6; the derivation in docs/models/slosh-modes.md):

    Gamma_j = rho sum_s A_s x_s eta_js           (kg^1/2 m: the mode's participation in x)
    m_j     = omega_j^2 Gamma_j^2 / k_j          (kg: its slosh mass, the x share)
    h_j     = rho int (z xi_x - x xi_z) dV / Gamma_j      (m: the slosh mass's height)

with k_j = eta_j^T K eta_j the mode's stiffness (g for a free surface under gravity g; with
a membrane on the surface, its tension's share added). The height is SP-106's for a free
surface, whose moment about the tank's centre is the moved liquid's weight and its
momentum's: a membrane pinned to the wall adds the rim's force, which that form has no
term for, so a tensioned surface's h_j and hinge are not given (NaN).

and the pendulum of the same mode has length g / omega_j^2, hinged at h_j + g / omega_j^2.
The masses of all modes sum to at most the liquid's (the rest is the fixed mass), and
sum_j m_j / (M omega_j^2) is the static lateral compliance |z_c| / g of a free surface.

A tank of revolution holds each lateral mode as a pair at one frequency. The cut cells of the
Cartesian grid are not mirror-symmetric (their fractions come from a fixed tetrahedral split
of each cube), so the grid splits the pair slightly (measured: 0.2 % in omega^2 on 16^3
cells, 0.07 % on 24^3 at half fill), and the eigensolver returns the two along +-45 deg.
:func:`lateral_pairs` rotates each pair closer than ``PAIR_RTOL`` into the one along x and
the one along y, as the time domain's pulse along x sees them.
"""
from __future__ import annotations

import time as _time
from dataclasses import dataclass

import numpy as np

from fluid.container import SphericalTank
from fluid.model import FluidModel
from fluid.modes import SurfaceModes, surface_modes
from fluid.solver import FluidSolver
from fluid.tank import tank_grid
from structure.volume import tank_volume

from fsi.slosh.limp import HeightSurface

PAIR_RTOL = 0.01
"""Two modes whose omega^2 differ by less than this fraction are one lateral pair of the tank
of revolution, split by the grid (module doc)."""
MAX_ORDER = 8
"""Highest azimuthal order :func:`azimuthal_order` tells apart."""


@dataclass(frozen=True)
class ModalSlosh:
    """One slosh mode's equivalent: ``omega`` rad/s, ``frequency_hz`` Hz, ``lambda1`` =
    omega^2 R / g (-), ``order`` its azimuthal order (0 axial, 1 lateral, ...), ``kind``
    ('axial', 'lateral' or 'higher'), ``direction_deg`` the direction of its lateral motion
    from +x (degrees, (-90, 90]; 0 for the others), ``participation_x`` and
    ``participation_y`` Gamma along x and y (kg^1/2 m), ``slosh_mass`` m, the x share (kg),
    ``slosh_mass_fraction`` m / M, ``lateral_mass`` its slosh mass along its own direction
    (kg), ``slosh_mass_height`` h (m, tank frame), ``pendulum_length`` g / omega^2 (m),
    ``hinge_height`` h + g / omega^2 (m), ``spring_stiffness`` m omega^2 (N/m)."""

    omega: float
    frequency_hz: float
    lambda1: float
    order: int
    kind: str
    direction_deg: float
    participation_x: float
    participation_y: float
    slosh_mass: float
    slosh_mass_fraction: float
    lateral_mass: float
    slosh_mass_height: float
    pendulum_length: float
    hinge_height: float
    spring_stiffness: float


def azimuthal_order(point: np.ndarray, area: np.ndarray, elevation: np.ndarray,
                    ring_width: float) -> int:
    """The azimuthal order m (0 .. ``MAX_ORDER``) whose harmonic carries most of the
    elevation ``elevation`` (k,) over the surface points ``point`` (k, 2) m with areas
    ``area`` (k,) m^2: sum over rings of width ``ring_width`` (m) about the axis of
    |sum A eta e^{-i m theta}|^2, the largest m."""
    r = np.hypot(point[:, 0], point[:, 1])
    theta = np.arctan2(point[:, 1], point[:, 0])
    ring = np.floor(r / ring_width).astype(int)
    power = []
    for m in range(MAX_ORDER + 1):
        weights = area * elevation * np.exp(-1j * m * theta)
        sums = np.bincount(ring, weights.real) + 1j * np.bincount(ring, weights.imag)
        power.append(float(np.sum(np.abs(sums) ** 2)) * (1.0 if m == 0 else 0.5))
    return int(np.argmax(power))


def lateral_pairs(omega2: np.ndarray, vectors: np.ndarray, participation: np.ndarray,
                  stiffness: np.ndarray | None = None, rtol: float = PAIR_RTOL):
    """Rotate each pair of modes closer than ``rtol`` in omega^2 whose participations
    (n, 2) both reach the lateral directions into the one along x and the one along y.
    ``vectors`` (..., n) the modes' fields (any number of leading axes, each mode's field on
    the last). Returns (omega2 (n,), vectors, participation (n, 2), stiffness (n,)), the
    pair's omega^2 the Rayleigh quotient of each rotated mode and its ``stiffness`` (n,)
    (each mode's eta^T K eta; the modes are K-orthogonal) likewise; ``stiffness`` None:
    ones."""
    omega2, vectors, participation = omega2.copy(), vectors.copy(), participation.copy()
    stiffness = np.ones(len(omega2)) if stiffness is None else np.array(stiffness, float)
    j = 0
    while j < len(omega2) - 1:
        k = j + 1
        close = abs(omega2[k] - omega2[j]) <= rtol * abs(omega2[j])
        norms = np.linalg.norm(participation[[j, k]], axis=1)
        if not (close and np.all(norms > 1e-9 * max(norms.max(), 1e-300))):
            j += 1
            continue
        angle = np.arctan2(participation[k, 0], participation[j, 0])
        c, s = np.cos(angle), np.sin(angle)
        rotation = np.array([[c, -s], [s, c]])  # columns: the x mode, the y mode
        vectors[..., [j, k]] = vectors[..., [j, k]] @ rotation
        participation[[j, k]] = rotation.T @ participation[[j, k]]
        omega2[[j, k]] = rotation.T**2 @ omega2[[j, k]]
        stiffness[[j, k]] = rotation.T**2 @ stiffness[[j, k]]
        j += 2
    return omega2, vectors, participation, stiffness


def modal_slosh(modes, model, radius: float, gravity: float, liquid_mass: float) \
        -> tuple[list[ModalSlosh], np.ndarray]:
    """The :class:`ModalSlosh` of each mode of ``modes`` (:class:`fluid.modes.SurfaceModes`)
    of ``model``'s liquid (mass ``liquid_mass`` kg) in a tank of ``radius`` (m) under gravity
    ``gravity`` (m/s^2) along -z, lateral pairs rotated to x and y (:func:`lateral_pairs`),
    and the modes' elevations (k, n) m per sqrt(kg) so rotated."""
    g = model.grid
    rho = model.density
    surface = modes.surface
    point = surface.point[modes.faces]
    eta = modes.elevation
    participation = rho * np.stack([point[:, 0] @ (modes.area[:, None] * eta),
                                    point[:, 1] @ (modes.area[:, None] * eta)], axis=1)
    fields = np.concatenate([eta, modes.face_displacement], axis=0)
    omega2, fields, participation, stiffness = lateral_pairs(modes.omega2, fields,
                                                             participation, modes.stiffness)
    eta, displacement = fields[:len(eta)], fields[len(eta):]
    moment = rho * _moment(model, surface, displacement)
    out = []
    for j, w2 in enumerate(omega2):
        gx, gy = participation[j]
        order = azimuthal_order(point, modes.area, eta[:, j], g.spacing)
        kind = {0: "axial", 1: "lateral"}.get(order, "higher")
        lateral = w2 * (gx * gx + gy * gy) / stiffness[j]
        mass = w2 * gx * gx / stiffness[j]
        direction = float(np.degrees(np.arctan2(gy, gx))) if kind == "lateral" else 0.0
        if direction <= -90.0:
            direction += 180.0
        elif direction > 90.0:
            direction -= 180.0
        height = float(moment[j] / gx) if abs(gx) > 1e-12 * abs(gy) + 1e-300 \
            and modes.tension == 0 else np.nan
        length = gravity / w2
        omega = float(np.sqrt(w2))
        out.append(ModalSlosh(
            omega=omega, frequency_hz=omega / (2 * np.pi), lambda1=w2 * radius / gravity,
            order=order, kind=kind, direction_deg=direction, participation_x=float(gx),
            participation_y=float(gy), slosh_mass=float(mass),
            slosh_mass_fraction=float(mass / liquid_mass), lateral_mass=float(lateral),
            slosh_mass_height=height, pendulum_length=length, hinge_height=height + length,
            spring_stiffness=float(mass * w2)))
    return out, eta


def _moment(model, surface, displacement: np.ndarray) -> np.ndarray:
    """(n,) m^4 per sqrt(kg) ...: int (z xi_x - x xi_z) dV of each mode's face displacement
    (n_faces, n) along FiPy's normals, each face standing for its wetted area times the
    distance between its cells' centres (the liquid's part theta h at a surface face)."""
    g = model.grid
    beta = surface.view.face_fraction
    length = g.face_distance.copy()
    length[surface.faces] *= surface.theta
    volume = beta * g.face_area * length
    centre = model.grid_points(g.face_centre)
    along = displacement * g.face_sign[:, None]  # along +axis
    x_faces = g.face_axis == 0
    z_faces = g.face_axis == g.vertical_axis
    return (volume[x_faces] * centre[x_faces, 2]) @ along[x_faces] - \
        (volume[z_faces] * centre[z_faces, 0]) @ along[z_faces]


@dataclass(frozen=True)
class TankModes:
    """The slosh modes of the rigid spherical tank at one tank fraction: the liquid's
    ``model`` and ``geometry`` at rest under the ``level`` (m), its ``modes``
    (:class:`fluid.modes.SurfaceModes`), their ``equivalents`` (:class:`ModalSlosh`, lateral
    pairs rotated to x and y) and ``elevation`` (k, n) m per sqrt(kg) so rotated, the
    liquid's ``mass`` (kg), its centroid's height ``centre_height`` (m) and the ``seconds``
    it took."""

    model: FluidModel
    geometry: object
    level: float
    modes: SurfaceModes
    equivalents: list
    elevation: np.ndarray
    mass: float
    centre_height: float
    seconds: float

    def first(self, kind: str) -> ModalSlosh | None:
        """The lowest mode of ``kind`` ('lateral' with a slosh mass along x, 'axial'), or
        None when none is among those computed."""
        return next((e for e in self.equivalents if e.kind == kind
                     and (kind != "lateral" or e.slosh_mass > 0)), None)


def tank_modes(radius: float, fill: float, cells: int, density: float, body, count: int,
               tension: float = 0.0) -> TankModes:
    """The first ``count`` slosh modes of the limp surface (the free surface) in a sphere of
    ``radius`` (m) at tank fraction ``fill`` = V / (4/3 pi R^3), liquid of ``density``
    (kg/m^3) under the body acceleration ``body`` (3,) m/s^2 (along -z), on the 3-D tank grid
    of ``cells`` cells moved so that the level is a plane of faces
    (:func:`fluid.tank.tank_grid`); ``tension`` (N/m): a massless flat membrane of that
    uniform tension on the level, pinned at the wall (:func:`fluid.modes.surface_modes`)."""
    body = np.asarray(body, dtype=float)
    tank = SphericalTank(radius)
    level = tank.level_holding(fill * tank_volume(radius))
    tic = _time.perf_counter()
    grid = tank_grid(radius, cells, axisymmetric=False, face_at=level)
    model = FluidModel(grid=grid, container=tank, density=density, viscosity=0.0,
                       body_acceleration=body, convection=False,
                       interface_condition="free-linear")
    heights = HeightSurface(grid, bottom=-2.0 * radius)
    geometry = FluidSolver(model, heights.interface(heights.flat(level))).state.geometry
    modes = surface_modes(model, geometry, count, tension=tension)
    mass = density * geometry.liquid_volume
    equivalents, elevation = modal_slosh(modes, model, radius, -float(body[2]), mass)
    return TankModes(model, geometry, level, modes, equivalents, elevation, mass,
                     tank.centroid_below(level), _time.perf_counter() - tic)
