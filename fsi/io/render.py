"""3-D renders of the diaphragm in its tank (PyVista, off screen), as ParaView would show them.

A render (:class:`View`) holds one frame of a membrane group of ``result.h5``:

* the membrane's triangles (:func:`structure.grid.triangles_from_quads`), lit and smooth
  shaded, coloured by a field of :data:`FIELDS` (von Mises stress, the largest principal log
  strain, the displacement's magnitude) with a colourbar titled with its units;
* the liquid, the region inside the tank below the sheet (the rim is clamped at the equator
  z = 0; the liquid lies between the sheet and the tank's bottom, and the sheet rises and
  inverts into the upper hemisphere as the tank fills), drawn as its boundary on the tank,
  the wetted wall, translucent blue (:func:`wetted_wall`; the sheet is the rest of its
  boundary);
* the tank, a translucent sphere of the result's ``attrs["radius"]``, with its equator (the
  clamp) drawn as a line;
* a title with the frame's tank fraction V / (4/3 pi R^3), and optionally a marked point
  (a peak) with its text.

:class:`Renderer` keeps one off-screen plotter (window :data:`WINDOW`) for all the renders of
one plot call and closes it. Where PyVista cannot be imported or its render window cannot be
made (tried in a child process, which VTK may stop), :func:`renderer_available` says why
and :func:`usable` logs one line
"3-D plots skipped: <reason>" (once per reason) so that the callers skip their 3-D plots.
"""
from __future__ import annotations

import functools
import logging
import os
import sys
from dataclasses import dataclass, field as dataclass_field, replace
from pathlib import Path
from typing import Callable

import numpy as np

from structure.grid import triangles_from_quads
from structure.topology import free_triangles

log = logging.getLogger(__name__)

WINDOW = (900, 700)
"""Render window (width, height), pixels."""
CMAP = "YlOrRd"
"""Colour map of the sheet's fields: no blue, which is the liquid's."""
ABOVE_COLOUR = "#6a00a8"
"""The colour of values above the colour scale's top (a clipped scale)."""
LIQUID_COLOUR, LIQUID_OPACITY = "#2b7bba", 0.35
TANK_COLOUR, TANK_OPACITY = "#b0b0b0", 0.12


@dataclass(frozen=True)
class Camera:
    """Where the camera looks from: elevation above the equator's plane and azimuth from +x
    (deg), distance from the focus in tank radii, focus (x, y, z) in tank radii."""
    elevation_deg: float = 28.0
    azimuth_deg: float = -55.0
    distance: float = 4.4
    focus: tuple[float, float, float] = (0.0, 0.0, -0.12)

    def position(self, radius: float) -> list[tuple[float, float, float]]:
        """PyVista's camera position [eye, focus, up] (m) for a tank of ``radius`` (m)."""
        el, az = np.radians(self.elevation_deg), np.radians(self.azimuth_deg)
        focus = radius * np.asarray(self.focus)
        eye = focus + self.distance * radius * np.array(
            [np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
        return [tuple(eye), tuple(focus), (0.0, 0.0, 1.0)]


OBLIQUE_ABOVE = Camera()
"""The default view: obliquely from above the rim, so that the sheet's upper side (and its
folds) is seen over the near rim and the liquid below the rim through the tank's near wall."""
FACING_TILT = 0.2
"""A sheet's upper normal tilted less than this (sine) from vertical faces every azimuth."""
VIEWS_TRIED = tuple((elevation, azimuth) for elevation in (28.0, 45.0, 65.0, -25.0)
                    for azimuth in range(-180, 180, 30))
"""(elevation, azimuth) deg of the cameras tried, in order, for a point hidden from the
camera facing it (:func:`camera_seeing`)."""


def _nearest_triangle(frame: Frame, point: np.ndarray) -> int:
    corners = frame.position[frame.triangles]
    return int(np.argmin(np.linalg.norm(corners.mean(axis=1) - point, axis=1)))


def camera_facing(frame: Frame, point: np.ndarray, base: Camera = OBLIQUE_ABOVE) -> Camera:
    """``base`` turned about the tank's axis to face the sheet's upper side at ``point``
    (3,) m (the inside of a hanging bowl from across the tank, an inverted dome from its own
    side); ``base`` where the sheet there is nearly level."""
    corners = frame.position[frame.triangles[_nearest_triangle(frame, point)]]
    normal = np.cross(corners[1] - corners[0], corners[2] - corners[0])
    normal *= np.sign(normal[2]) or 1.0
    if np.hypot(normal[0], normal[1]) < FACING_TILT * np.linalg.norm(normal):
        return base
    return replace(base, azimuth_deg=float(np.degrees(np.arctan2(normal[1], normal[0]))))


def hidden(frame: Frame, point: np.ndarray, eye: np.ndarray) -> bool:
    """Whether the sheet hides ``point`` (3,) m from ``eye`` (3,) m: a triangle not touching
    the point's own crosses the line between them (Moller-Trumbore)."""
    own = frame.triangles[_nearest_triangle(frame, point)]
    others = frame.triangles[~np.isin(frame.triangles, own).any(axis=1)]
    a, b, c = (frame.position[others[:, i]] for i in range(3))
    ray = point - eye
    e1, e2 = b - a, c - a
    p = np.cross(ray, e2)
    det = np.einsum("ij,ij->i", e1, p)
    ok = np.abs(det) > 1e-300
    det = np.where(ok, det, 1.0)
    s = eye - a
    u = np.einsum("ij,ij->i", s, p) / det
    q = np.cross(s, e1)
    v = (q @ ray) / det
    t = np.einsum("ij,ij->i", e2, q) / det
    return bool(np.any(ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0) & (t < 1)))


def camera_seeing(frame: Frame, point: np.ndarray, base: Camera = OBLIQUE_ABOVE) -> Camera:
    """A camera from which the sheet does not hide ``point`` (3,) m: the one facing it
    (:func:`camera_facing`), else the first of :data:`VIEWS_TRIED` (``base`` otherwise
    kept), else the facing one."""
    facing = camera_facing(frame, point, base)
    tried = [facing] + [replace(base, elevation_deg=e, azimuth_deg=float(a))
                        for e, a in VIEWS_TRIED]
    return next((c for c in tried
                 if not hidden(frame, point, np.asarray(c.position(frame.radius)[0]))), facing)


# --- frames and their fields ---------------------------------------------------------------

@dataclass(frozen=True)
class Frame:
    """One membrane frame: ``position`` (n, 3) m, ``rest`` (n, 3) m, ``triangles`` (m, 3)
    node indices, ``sheet`` (m,) bool the free sheet's triangles, ``data`` the frame's slice
    of its group's per-frame datasets (name -> array, SI units), ``radius`` the tank's (m)."""
    position: np.ndarray
    rest: np.ndarray
    triangles: np.ndarray
    sheet: np.ndarray
    data: dict
    radius: float


def frame_of(res: dict, group: str, k: int) -> Frame:
    """Frame ``k`` of membrane group ``group`` of a result read by
    :func:`fsi.io.output.read_result`."""
    g, m = res[group], res["membrane"]
    tri = triangles_from_quads(m["face_nodes"])
    n_frames = len(g["node_position"])
    data = {name: value[k] for name, value in g.items()
            if isinstance(value, np.ndarray) and value.ndim >= 1 and len(value) == n_frames}
    return Frame(position=np.asarray(g["node_position"][k], dtype=float),
                 rest=np.asarray(m["rest_position"], dtype=float), triangles=tri,
                 sheet=free_triangles(m["fixed"], tri), data=data,
                 radius=float(res["attrs"]["radius"]))


@dataclass(frozen=True)
class Field:
    """A colouring of the sheet: ``values(frame)`` (m,) per triangle or (n,) per node in SI
    units, ``quantity`` its name, ``unit`` the shown units, ``scale`` SI -> those units,
    ``dataset`` the per-frame dataset it needs (None: the positions only)."""
    values: Callable[[Frame], np.ndarray]
    quantity: str
    unit: str
    scale: float
    dataset: str | None = None

    @property
    def label(self) -> str:
        """The colourbar's title: the quantity and its units."""
        return f"{self.quantity} ({self.unit})"

    def shown(self, frame: Frame) -> np.ndarray:
        """The values in the shown units, (m,) or (n,)."""
        return self.scale * np.asarray(self.values(frame), dtype=float)

    def available(self, group: dict) -> bool:
        """Whether a group of frames holds what the field needs."""
        return self.dataset is None or self.dataset in group


FIELDS: dict[str, Field] = {
    "von_mises": Field(lambda f: f.data["von_mises_stress"], "von Mises stress", "MPa", 1e-6,
                       "von_mises_stress"),
    "log_strain": Field(lambda f: f.data["log_strain"][:, 0], "max principal log strain", "-",
                        1.0, "log_strain"),
    "displacement": Field(lambda f: np.linalg.norm(f.position - f.rest, axis=1),
                          "displacement magnitude", "mm", 1e3),
}
"""Field name -> :class:`Field`."""


def first_available(group: dict, names=("von_mises", "displacement")) -> str:
    """The first of ``names`` whose dataset ``group`` holds (a run without its stress
    analysis is coloured by the displacement)."""
    return next(n for n in names if FIELDS[n].available(group))


def sheet_values(frame: Frame, name: str) -> np.ndarray:
    """Field ``name`` on the free sheet only, shown units: per triangle (k,) or per node of
    a free triangle (j,)."""
    values = FIELDS[name].shown(frame)
    if len(values) == len(frame.triangles):
        return values[frame.sheet]
    return values[np.unique(frame.triangles[frame.sheet])]


def percentile_scale(values: np.ndarray, top: float = 99.0) -> tuple[float, float]:
    """Colour scale (low, high) for ``values``: 0 (or the 1st percentile where lower) up to
    the ``top`` percentile."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if v.size == 0:
        return 0.0, 1.0
    low, high = min(0.0, float(np.percentile(v, 100 - top))), float(np.percentile(v, top))
    return low, high if high > low else low + 1.0


def peak_point(frame: Frame, name: str) -> tuple[np.ndarray, float]:
    """Where on the free sheet field ``name`` is largest ((3,) m: the triangle's centroid or
    the node) and its value (shown units)."""
    values = FIELDS[name].shown(frame)
    per_triangle = len(values) == len(frame.triangles)
    mask = frame.sheet if per_triangle else np.isin(
        np.arange(len(values)), frame.triangles[frame.sheet])
    i = int(np.argmax(np.where(mask & np.isfinite(values), values, -np.inf)))
    point = frame.position[frame.triangles[i]].mean(axis=0) if per_triangle \
        else frame.position[i]
    return point, float(values[i])


# --- the liquid ----------------------------------------------------------------------------

def _plan_pairs(corners: np.ndarray, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(triangle, point) index arrays of the points ``points`` (k, 3) m whose plan (x, y)
    lies within a triangle's plan circle about its centroid; ``corners`` (m, 3, 3) m."""
    from scipy.spatial import cKDTree

    centre = corners[:, :, :2].mean(axis=1)
    reach = np.linalg.norm(corners[:, :, :2] - centre[:, None, :], axis=2).max(axis=1)
    near = cKDTree(points[:, :2]).query_ball_point(centre, r=reach * (1 + 1e-9) + 1e-12)
    counts = np.fromiter((len(n) for n in near), dtype=np.int64, count=len(near))
    flat = np.concatenate([np.asarray(n, dtype=np.int64) for n in near]) if counts.sum() \
        else np.zeros(0, dtype=np.int64)
    return np.repeat(np.arange(len(corners)), counts), flat


def sheet_side(position: np.ndarray, triangles: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Which side of the sheet points ``points`` (k, 3) m lie on, (k,) m: minus, on the
    liquid's side, and plus, on the gas's, their vertical distance to the sheet. The sheet
    (``position`` (n, 3) m, ``triangles`` (m, 3)) is clamped at the equator and the liquid
    lies between it and the tank's bottom, so a point inside the tank is in the liquid when
    the vertical line above it crosses the sheet an odd number of times (the line leaves the
    tank through the upper hemisphere, which the liquid does not touch). Points with no
    crossing above and below are on the gas's side, at +inf."""
    corners = position[triangles]
    tri, pt = _plan_pairs(corners, points)
    a, b, c = corners[tri, 0], corners[tri, 1], corners[tri, 2]
    dx, dy = points[pt, 0] - a[:, 0], points[pt, 1] - a[:, 1]
    det = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1])
    det = np.where(np.abs(det) > 1e-300, det, np.nan)          # a triangle seen edge on
    u = (dx * (c[:, 1] - a[:, 1]) - dy * (c[:, 0] - a[:, 0])) / det
    v = (dy * (b[:, 0] - a[:, 0]) - dx * (b[:, 1] - a[:, 1])) / det
    hit = (u >= 0) & (v >= 0) & (u + v <= 1)
    height = (a[:, 2] + u * (b[:, 2] - a[:, 2]) + v * (c[:, 2] - a[:, 2]))[hit]
    gap = height - points[pt[hit], 2]
    above = np.bincount(pt[hit], weights=(gap > 0).astype(float), minlength=len(points))
    near = np.full(len(points), np.inf)
    np.minimum.at(near, pt[hit], np.abs(gap))
    return np.where(above.astype(np.int64) % 2 == 1, -near, near)


WETTED_OFFSET, TANK_OFFSET = 0.003, 0.006
"""The wetted wall and the tank are drawn these fractions of the radius outside the tank
wall (1), so that a sheet lying on the wall is seen in front of them from inside."""
FILM = 0.01
"""Liquid thinner than this fraction of the radius between the sheet and the wall (about
2 mm in the thesis's tank) is not drawn: there the sheet lies on the wall (1)."""


def wetted_wall(position: np.ndarray, triangles: np.ndarray, radius: float):
    """The liquid's boundary on the tank: the part of the lower tank wall on the liquid's
    side of the sheet (:func:`sheet_side`) by more than :data:`FILM` across the wall,
    pyvista.PolyData (m) just outside the tank (:data:`WETTED_OFFSET`), clipped along the
    sheet's contact line; empty without liquid."""
    import pyvista as pv

    wall = pv.Sphere(radius=radius * (1 + WETTED_OFFSET), theta_resolution=180,
                     phi_resolution=90)
    wall = wall.clip(normal="z", origin=(0, 0, 0.02 * radius))    # the liquid's hemisphere
    points = np.asarray(wall.points, dtype=float)
    side = np.clip(sheet_side(position, triangles, points), -radius, radius)
    depth = -side * np.abs(points[:, 2]) / np.linalg.norm(points, axis=1)  # across the wall
    wall.point_data["dry"] = FILM * radius - depth
    return wall.clip_scalar(scalars="dry", value=0.0)


# --- what one render shows -----------------------------------------------------------------

@dataclass(frozen=True)
class Mark:
    """A marked point (3,) m with its label."""
    point: np.ndarray
    text: str


@dataclass
class View:
    """One render: ``frame`` coloured by field ``field`` (a key of :data:`FIELDS`) over
    ``clim`` (shown units; None: the frame's own range), ``title`` at the top (None: none),
    ``note`` at the bottom, ``mark`` a marked point, ``liquid`` and ``colourbar`` whether to
    draw them, ``camera``."""
    frame: Frame
    field: str = "von_mises"
    clim: tuple[float, float] | None = None
    title: str | None = None
    note: str | None = None
    mark: Mark | None = None
    liquid: bool = True
    colourbar: bool = True
    camera: Camera = dataclass_field(default_factory=lambda: OBLIQUE_ABOVE)


def sheet_mesh(frame: Frame, name: str):
    """The membrane's triangles as pyvista.PolyData (m) with field ``name`` (shown units)
    as cell or point data ``"value"``."""
    import pyvista as pv

    tri = frame.triangles
    mesh = pv.PolyData(frame.position, np.column_stack([np.full(len(tri), 3), tri]).ravel())
    values = FIELDS[name].shown(frame)
    if len(values) == len(tri):
        mesh.cell_data["value"] = values
    else:
        mesh.point_data["value"] = values
    return mesh


def _scalar_bar_args(label: str) -> dict:
    return dict(title=label, vertical=True, position_x=0.86, position_y=0.18, width=0.05,
                height=0.62, title_font_size=16, label_font_size=14, n_labels=6, fmt="%.3g",
                color="black", font_family="arial")


def nice_ticks(clim: tuple[float, float]) -> np.ndarray:
    """Round tick values inside ``clim`` (low, high), with ``high`` itself."""
    from matplotlib.ticker import MaxNLocator

    ticks = MaxNLocator(nbins=5).tick_values(*clim)
    ticks = ticks[(ticks >= clim[0]) & (ticks < clim[1] - 0.08 * (clim[1] - clim[0]))]
    return np.r_[ticks, clim[1]]


def _label_colourbar(bar, clim: tuple[float, float]) -> None:
    """Round labels and the top value on a vtkScalarBarActor (the swatch of values above
    the scale, where drawn, is named in the render's note)."""
    from vtkmodules.util.numpy_support import numpy_to_vtk

    bar.SetUseCustomLabels(True)
    bar.SetCustomLabels(numpy_to_vtk(nice_ticks(clim), deep=True))
    bar.SetDrawAnnotations(False)
    bar.SetVerticalTitleSeparation(10)


def colour_scale(view: View) -> tuple[float, float]:
    """The view's colour scale (low, high), shown units: its own, or the frame's range."""
    return view.clim or percentile_scale(FIELDS[view.field].shown(view.frame), 100.0)


def above_scale(view: View) -> bool:
    """Whether some of the sheet's values lie above the colour scale's top."""
    values = FIELDS[view.field].shown(view.frame)
    return bool(np.any(values[np.isfinite(values)] > colour_scale(view)[1] * (1 + 1e-9)))


ABOVE_NOTE = "purple: above the colour scale"
NAN_COLOUR = "#d9d9d9"
"""The colour of a triangle without a value (its stresses could not be computed)."""


def _draw_sheet(plotter, view: View) -> None:
    """The membrane coloured by the view's field, with its colourbar."""
    mesh = sheet_mesh(view.frame, view.field)
    clim, clipped = colour_scale(view), above_scale(view)
    label = FIELDS[view.field].label
    plotter.add_mesh(mesh, scalars="value", cmap=CMAP, clim=clim, smooth_shading=True,
                     split_sharp_edges=False, specular=0.3, specular_power=20, ambient=0.15,
                     diffuse=0.85, above_color=ABOVE_COLOUR if clipped else None,
                     nan_color=NAN_COLOUR, show_scalar_bar=view.colourbar,
                     scalar_bar_args=_scalar_bar_args(label))
    if view.colourbar:
        _label_colourbar(plotter.scalar_bars[label], clim)


def _draw_tank(plotter, view: View) -> None:
    """The tank, translucent, and its equator."""
    import pyvista as pv

    radius = view.frame.radius
    plotter.add_mesh(pv.Sphere(radius=radius * (1 + TANK_OFFSET), theta_resolution=90,
                               phi_resolution=45),
                     color=TANK_COLOUR, opacity=TANK_OPACITY, smooth_shading=True,
                     specular=0.2)
    t = np.linspace(0.0, 2 * np.pi, 181)
    ring = np.column_stack([radius * np.cos(t), radius * np.sin(t), np.zeros_like(t)])
    plotter.add_lines(ring, color="#595959", width=2, connected=True)


def _draw_liquid(plotter, view: View) -> None:
    """The wetted wall, translucent blue, where the view draws the liquid and there is
    some."""
    if not view.liquid:
        return
    frame = view.frame
    liquid = wetted_wall(frame.position, frame.triangles, frame.radius)
    if liquid.n_points:
        plotter.add_mesh(liquid, color=LIQUID_COLOUR, opacity=LIQUID_OPACITY,
                         smooth_shading=True, specular=0.4, specular_power=30)


MARK_COLOUR = "#00b4ff"
"""The marked point's colour (the 2-D plots star the peak in it too)."""
MARK_SIZE, MARK_LIFT = 0.022, 0.35
"""The marked point's sphere radius and the height of its label above it, in tank radii."""


def _draw_mark(plotter, view: View) -> None:
    """The view's marked point, if any: a sphere at the point, a leader line up to its
    label."""
    import pyvista as pv

    if view.mark is None:
        return
    mark, radius = view.mark, view.frame.radius
    point = np.asarray(mark.point, dtype=float)
    anchor = point + np.array([0.0, 0.0, MARK_LIFT * radius])
    plotter.add_mesh(pv.Sphere(radius=MARK_SIZE * radius, center=point), color=MARK_COLOUR,
                     smooth_shading=True)
    plotter.add_mesh(pv.Line(point, anchor), color="black", line_width=2)
    plotter.add_point_labels(anchor[None, :], [mark.text], font_size=15, bold=True,
                             shape_color="white", shape_opacity=0.85, always_visible=True,
                             show_points=False, margin=4)


def _draw_text(plotter, view: View) -> None:
    """The title at the top, the note (and what the colourbar's top swatch means) at the
    bottom."""
    if view.title:
        plotter.add_text(view.title, position="upper_edge", font_size=10, color="black")
    swatch = view.colourbar and above_scale(view)     # the note explains the colourbar's
    note = "\n".join(t for t in (view.note, swatch and ABOVE_NOTE) if t)
    if note:
        plotter.add_text(note, position="lower_edge", font_size=8, color="black")


SCENE_PARTS: dict[str, Callable] = {"tank": _draw_tank, "liquid": _draw_liquid,
                                     "sheet": _draw_sheet, "mark": _draw_mark,
                                     "text": _draw_text}
"""What a render draws, in order (name -> draw(plotter, view))."""


# --- the renderer --------------------------------------------------------------------------

def _prefer_offscreen_window() -> None:
    """Without a display, VTK's default X window cannot be made: ask for EGL (before VTK is
    imported)."""
    if sys.platform.startswith("linux") and not os.environ.get("DISPLAY") \
            and not os.environ.get("WAYLAND_DISPLAY"):
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")


WINDOW_PROBE = """
import vtkmodules.vtkRenderingOpenGL2
from vtkmodules.vtkRenderingCore import vtkRenderWindow, vtkRenderer
window = vtkRenderWindow()
window.SetOffScreenRendering(1)
window.SetSize(8, 8)
window.AddRenderer(vtkRenderer())
window.Render()
print(window.SupportsOpenGL())
"""
"""Makes an off-screen render window and draws into it, in a child process: where the
window cannot be made VTK may stop the process (an X window without a display does)."""
PROBE_SECONDS = 120.0


@functools.cache
def renderer_available() -> tuple[bool, str]:
    """(True, "") when PyVista imports and an off-screen render window can be made and
    drawn into (:data:`WINDOW_PROBE`); else (False, the reason in a few words)."""
    _prefer_offscreen_window()
    try:
        import pyvista  # noqa: F401
    except Exception as exc:  # ImportError, or VTK's own failure to load
        return False, f"pyvista cannot be imported ({type(exc).__name__}: {exc})"
    reason = _window_problem()
    return (False, f"no off-screen render window ({reason})") if reason else (True, "")


def _window_problem() -> str:
    """Why :data:`WINDOW_PROBE` fails ('' where it works)."""
    import subprocess

    try:
        probe = subprocess.run([sys.executable, "-c", WINDOW_PROBE], capture_output=True,
                               text=True, timeout=PROBE_SECONDS)
    except subprocess.TimeoutExpired:
        return f"no window after {PROBE_SECONDS:.0f} s"
    if probe.returncode < 0:
        return f"VTK stopped by signal {-probe.returncode}"
    if probe.returncode:
        lines = [line for line in probe.stderr.splitlines() if line.strip()]
        return lines[-1].strip()[-160:] if lines else f"exit status {probe.returncode}"
    return "" if probe.stdout.strip().endswith("1") else "the window has no OpenGL"


_REPORTED: set[str] = set()


def usable() -> bool:
    """Whether 3-D plots can be made; where not, logs "3-D plots skipped: <reason>" (once
    per reason in a process)."""
    ok, reason = renderer_available()
    if not ok and reason not in _REPORTED:
        _REPORTED.add(reason)
        log.warning("3-D plots skipped: %s", reason)
    return ok


class Renderer:
    """One off-screen plotter of ``window`` (width, height) pixels for several renders;
    use as a context manager (the plotter is closed on leaving)."""

    def __init__(self, window: tuple[int, int] = WINDOW):
        _prefer_offscreen_window()
        import pyvista as pv

        self.plotter = pv.Plotter(off_screen=True, window_size=list(window))
        self.plotter.set_background("white")

    def __enter__(self) -> "Renderer":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        self.plotter.close()

    def image(self, view: View) -> np.ndarray:
        """The render of ``view``, (height, width, 3) uint8 RGB."""
        p = self.plotter
        p.suppress_rendering = True          # one render, at the screenshot
        p.clear()
        for draw in SCENE_PARTS.values():
            draw(p, view)
        p.camera_position = view.camera.position(view.frame.radius)
        p.camera.view_angle = 30.0
        p.suppress_rendering = False
        p.render()
        return p.screenshot(return_img=True)

    def save(self, view: View, path: Path) -> Path:
        """Write the render of ``view`` to ``path`` (PNG) and return it."""
        from PIL import Image

        Image.fromarray(self.image(view)).save(path)
        return Path(path)
