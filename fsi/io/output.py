"""Result files: ``result.h5`` (h5py) and an XDMF time series (meshio) for ParaView.

Layout of ``result.h5`` (the documentation's output table is :func:`reference_markdown`):

    attrs: scene (TOML text), scene_name, procedure, plus run facts (volumes in m^3, seconds)
    /membrane/rest_position   (n_nodes, 3) float64, m
    /membrane/face_nodes      (n_faces, 4) int64, quads
    /membrane/fixed           (n_nodes,) bool
    /<group>/node_position    (n_frames, n_nodes, 3) float64, m
    /<group>/tank_fraction    (n_frames,) -, measured V / (4/3 pi R^3)
    /<group>/liquid_volume    (n_frames,) m^3
    /<group>/pressure_level   (n_frames,) Pa, uniform pressure level p_ref at the tank centre
    /<group>/equivalent_height (n_frames,) m, equivalent fluid height h = p_ref / (rho |b|)
    /<group>/wall_seconds     (n_frames,) s
    ... and the other per-frame datasets a procedure records (each with a ``units`` attribute).

The groups are :data:`GROUPS`. The XDMF series
(membrane frames only, on the triangles of the stress fields, with the cell data of
:data:`XDMF_CELL_FIELDS`) is stamped with ``frames/time`` where there is one, else with the fill
fraction.

A float dataset holds no NaN or infinity: an entry that does not apply to its record (the
level of an empty tank) is the dataset's ``_FillValue`` (:data:`FILL_VALUES`), which
:func:`read_result`, netCDF and xarray read as missing.

Files are written into a temporary folder inside the output folder and moved into place only
when complete, so an interrupted run leaves no half-written result.
"""
from __future__ import annotations

import logging
import os
import shutil
import tempfile
from pathlib import Path

import h5py
import meshio
import numpy as np

from structure.grid import triangles_from_quads

log = logging.getLogger(__name__)

UNITS = {
    "node_position": "m", "inversion_fraction": "1", "target_fill": "1",
    "liquid_volume": "m^3", "pressure_level": "Pa", "equivalent_height": "m",
    "pressure_level_before": "Pa",
    "wall_seconds": "s", "relaxation_steps": "1", "converged": "1", "strain_error": "1",
    "strain_max": "1", "time": "s", "node_speed_max": "m/s",
    "node_velocity": "m/s", "interface_pressure": "Pa", "fluid_liquid_volume": "m^3",
    "tank_fraction": "1", "fluid_speed_max": "m/s", "coupling_iterations": "1",
    "residual_pressure": "1", "residual_points": "1", "seconds_structure": "s",
    "seconds_fluid": "s", "port_flow": "m^3/s", "delivered_volume": "m^3",
    "surface_height": "m", "node_plan": "m", "node_area": "m^2", "momentum": "kg m/s",
    "angular_momentum": "kg m^2/s", "liquid_kinetic_energy": "J", "potential_energy": "J",
    "dissipation_rate": "W", "dissipated_energy": "J", "tank_acceleration": "m/s^2",
    "force": "N", "moment": "N m", "centre_of_mass": "m", "membrane_kinetic_energy": "J",
    "membrane_elastic_energy": "J", "membrane_liquid_volume": "m^3", "node_mass": "kg",
    "pressure": "Pa", "radial_position": "m", "tank_radius": "m", "fluid_interface_shift": "m",
    "mode": "1", "azimuthal_order": "1", "direction_deg": "deg", "eigenvalue": "1",
    "elevation": "m/kg^0.5", "surface_faces": "1", "liquid_mass": "kg",
    "lambda1": "1", "frequency_hz": "Hz", "omega": "rad/s", "slosh_mass_fraction": "1",
    "pendulum_length": "m", "spring_stiffness": "N/m", "static_compliance": "s^2",
    "modal_compliance": "s^2", "level": "m", "unstable_directions": "1", "membrane_dofs": "1",
    "principal_resultant": "N/m", "principal_direction": "1", "principal_stress": "Pa",
    "bending_stress": "Pa", "surface_stress": "Pa", "von_mises_stress": "Pa",
    "green_strain": "1", "log_strain": "1", "thickness": "m", "fold_count": "1",
    "inverted_area_fraction": "1", "inversion_front_deg": "deg", "wall_contact_area": "m^2",
    "self_contact_nodes": "1", "stress_valid": "1", "peak_stress": "Pa", "peak_strain": "1", "polar_deg": "deg",
    "azimuth_deg": "deg", "event": "1 (text)", "area": "m^2", "triangle": "1",
    "stress_range": "Pa", "mean_stress": "Pa", "count": "1",
    "meridian_radius": "m", "meridian_height": "m", "meridian_stretch": "1",
    "meridian_stress": "Pa", "meridian_moment": "N m/m", "meridian_arc_length": "m",
    "harmonic_eigenvalue": "1/s^2", "wave_number": "1", "critical_wave_number": "1",
    "stable": "1", "axisymmetric_stable": "1", "lobes": "1", "lambda1_free": "1",
    "free_slosh_mass_fraction": "1", "lambda1_lowest": "1", "lowest_slosh_mass_fraction": "1",
    "wet_gap_order": "1",
}

UNIT_PREFIXES = {"deflection_": "m", "centre_deflection_": "m", "valid_": "1"}
"""Units of the per-estimate datasets of a plate-estimate run (``deflection_small``, ...)."""

ATTR_UNITS = {
    "lambda1": "1", "zeta": "1", "omega": "rad/s", "frequency_hz": "Hz", "radius": "m",
    "pendulum_length": "m", "spring_stiffness": "N/m", "peak_force_x": "N",
    "peak_moment_y": "N m", "static_compliance": "s^2", "modal_compliance": "s^2",
    "slosh_mass_fraction": "1", "target_tank_fraction": "1", "level": "m",
    "run_seconds": "s", "seconds_per_period": "s", "window": "s", "viscosity": "Pa s",
    "full_volume": "m^3", "full_tank_fraction": "1", "empty_volume": "m^3", "start_volume": "m^3", "port_stub_volume": "m^3",
    "start_pressure_level": "Pa", "start_seed_amplitude": "m", "start_seed_wave_number": "1",
    "substep": "s", "centre_of_mass_amplitude": "m",
    "first_mode_bound_hz": "Hz", "miner_damage": "1", "miner_damage_triangle": "1",
    "peak_stress_triangle": "1", "peak_strain_triangle": "1", "peak_stress_membrane": "Pa",
    "dynamic_amplification": "1", "stress_margin": "1", "strain_margin": "1",
}
"""Units of the run facts (result attributes) a sweep's dataset gathers."""

UNIT_SUFFIXES = {"_std": None, "_time": "s", "_tank_fraction": "1", "_deg": "deg", "_height": "m", "_mass": "kg", "_hz": "Hz", "_seconds": "s",
                 "_volume": "m^3"}
"""Units by the name's ending (``_std``: the units of the name without it)."""


GROUPS = {
    "membrane": "the membrane's rest shape and topology (rest_position, face_nodes, fixed)",
    "frames": "the main sequence: the fill, the thesis frames picked by volume, the coupled "
              "fill's frames in time, or a slosh run's surface heights in time",
    "full_inversion": "a static sweep's fully inverted equilibrium: 100 % of the thesis's fill "
                      "scale",
    "drain": "a static sweep's draining leg",
    "history": "every recorded thesis-ramp frame",
    "windows": "every coupling window of a coupled-fill or slosh run",
    "surface": "a slosh run's height-surface nodes",
    "plate": "the plate-estimate procedure's closed forms, one record per fill",
    "fills": "a modes run's first lateral mode and its spring-mass equivalent, one record "
             "per tank fraction",
    "modes": "a modes run's modes, one record per fill and mode",
    "shapes": "a modes run's mode shapes: the surface's elevation over the grid's columns, "
              "one record per fill",
    "envelope": "per membrane triangle over the main sequence: its largest principal stress "
                "and strain and when, and its place on the rest shape",
    "events": "the membrane's topology changes over the main sequence, one row each: folds "
              "forming and vanishing, wall contact, self-contact and inversion starting and "
              "ending",
    "axisymmetric_fill": "a shell-of-revolution run's fill, one record per tank fraction: the "
                         "level, the stability by circumferential wave number and the "
                         "meridian's fields",
    "axisymmetric_drain": "a shell-of-revolution run's drain, as axisymmetric_fill",
    "axisymmetric_events": "a shell-of-revolution run's snaps and onsets of folding, one row "
                           "each",
    "axisymmetric_slosh": "a shell-of-revolution run's n = 1 slosh mode on the fill's branch, "
                          "one record per slosh fill: lambda1, slosh mass, hinge height, and "
                          "the free surface's at the same fill",
    "limit_points": "a volume sweep's snaps crossed by the minimisation model, one row each: "
                    "the leg, the tank fraction, the levels before and after",
    "cycles": "the rainflow cycles of the stress of the most loaded triangles in a run in "
              "time, one row each",
}
"""Groups of ``result.h5`` -> what they hold."""


def reference_markdown() -> str:
    """The output reference (Markdown) generated from :data:`GROUPS`, :data:`UNITS`,
    :data:`ATTR_UNITS`, :data:`UNIT_PREFIXES` and :data:`UNIT_SUFFIXES`: the groups, the
    per-frame datasets with their units, the run facts (attributes) with theirs, and the rules
    by name."""
    def table(head, rows):
        return "\n".join([f"| {head[0]} | {head[1]} |", "|---|---|"]
                         + [f"| `{a}` | {b} |" for a, b in rows])
    suffixes = [(f"*{s}", u if u is not None else "the units of the name without it")
                for s, u in UNIT_SUFFIXES.items()]
    prefixes = [(f"{s}*", u) for s, u in UNIT_PREFIXES.items()]
    return "\n\n".join([
        table(("group", "holds"), GROUPS.items()),
        table(("dataset", "units"), sorted(UNITS.items())),
        table(("attribute", "units"), sorted(ATTR_UNITS.items())),
        table(("name pattern", "units"), prefixes + suffixes)])


def units_of(name: str) -> str:
    """The units of dataset ``name`` ('' where it has none)."""
    if name in UNITS or name in ATTR_UNITS:
        return UNITS.get(name, ATTR_UNITS.get(name))
    for suffix, unit in UNIT_SUFFIXES.items():
        if name.endswith(suffix):
            return units_of(name[:-len(suffix)]) if unit is None else unit
    return next((u for prefix, u in UNIT_PREFIXES.items() if name.startswith(prefix)), "")


MAIN_GROUP = "frames"
"""The main sequence of membrane frames: the XDMF series, the envelope and the events."""


def frame_stamp(group: dict) -> str:
    """What stamps a group's frames: ``time`` (s) where it has one, else ``tank_fraction``."""
    return "time" if "time" in group else "tank_fraction"


RESULT_FILE = "result.h5"
XDMF_FILE = "frames.xdmf"
XDMF_FILES = {MAIN_GROUP: XDMF_FILE, "drain": "drain.xdmf"}
"""Groups written as ParaView time series (the fill leg and a static sweep's draining leg)."""


def software_version() -> str:
    """This package's version (its metadata; 'unknown' when not installed)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("slosh-fsi")
    except PackageNotFoundError:
        return "unknown"


def write_result(out_dir: Path, scene, model, result) -> Path:
    """Write ``result.h5`` and ``frames.xdmf`` (+ its ``frames.h5``; ``drain.xdmf`` for a
    draining leg) into ``out_dir``, with the software version."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=".partial-", dir=out_dir))
    try:
        with h5py.File(tmp / RESULT_FILE, "w") as f:
            f.attrs["scene"] = scene.text
            f.attrs["scene_name"] = scene.name
            f.attrs["procedure"] = scene["scene"]["procedure"]
            f.attrs["radius"] = model.radius
            f.attrs["grid_size"] = model.grid_size
            f.attrs["software_version"] = software_version()
            for k, v in result.attrs.items():
                f.attrs[k] = v
            g = f.create_group("membrane")
            g["rest_position"] = model.node_rest_position
            g["face_nodes"] = model.face_nodes
            g["fixed"] = model.node_fixed
            g["rest_position"].attrs["units"] = "m"
            g["face_nodes"].attrs["units"] = "1 (node indices)"
            g["fixed"].attrs["units"] = "1 (true: a support node)"
            for name, frames in result.groups.items():
                grp = f.create_group(name)
                for key, arr in frames.items():
                    _write_dataset(grp, key, arr, f"{name}/{key}")
        for group, name in XDMF_FILES.items():
            if "node_position" in result.groups.get(group, {}):
                _write_xdmf(tmp, model, result.groups[group], name)
        for p in tmp.iterdir():
            os.replace(p, out_dir / p.name)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return out_dir / RESULT_FILE


FILL_VALUES = {np.dtype(np.float32): np.float32(9.96921e36),
               np.dtype(np.float64): np.float64(9.969209968386869e36)}
"""The value that stands for a missing entry of a float dataset (netCDF's default fill, so
that netCDF and xarray readers mask it), declared in the dataset's ``_FillValue`` attribute
(CF conventions, Sec. 2.5.1): a level where the tank is empty, the fields of a frame whose
stresses could not be computed. :func:`read_result` gives NaN in its place."""


def _write_dataset(group, key: str, data, name: str) -> None:
    """Write ``data`` as dataset ``key`` of ``group`` with its ``units``; a float dataset's
    NaN entries (not applicable to that record) as :data:`FILL_VALUES` with ``_FillValue``
    declared; an infinite entry is a missing one too, and logged (``name``)."""
    arr = np.asarray(data)
    fill = FILL_VALUES.get(arr.dtype)
    missing = fill is not None and not np.all(np.isfinite(arr))
    if missing:
        infinite = int(np.isinf(arr).sum())
        if infinite:
            log.warning("%s: %d infinite entries written as missing", name, infinite)
        arr = np.where(np.isfinite(arr), arr, fill)
    ds = group.create_dataset(key, data=arr)
    ds.attrs["units"] = units_of(key)
    if missing:
        ds.attrs["_FillValue"] = fill


def _read_dataset(ds) -> np.ndarray:
    """A dataset's values, NaN where it holds its ``_FillValue``."""
    value = ds[()]
    if "_FillValue" in ds.attrs:
        value = np.where(value == ds.attrs["_FillValue"], np.nan, value)
    return value


XDMF_CELL_FIELDS = {"von_mises_stress": None, "surface_stress": None,
                    "principal_stress": ("principal_stress_1", "principal_stress_2"),
                    "log_strain": ("log_strain_1", "log_strain_2"),
                    "principal_direction": None}
"""Per-triangle datasets written as XDMF cell data -> the names of their components written
as scalars (None: as they are)."""


def _write_xdmf(folder: Path, model, frames: dict, name: str) -> None:
    cells = [("triangle", triangles_from_quads(model.face_nodes))]
    cwd = os.getcwd()
    os.chdir(folder)  # meshio names its heavy-data file relative to the working folder
    try:
        with meshio.xdmf.TimeSeriesWriter(name) as writer:
            writer.write_points_cells(model.node_rest_position, cells)
            for k in range(frames["node_position"].shape[0]):
                disp = frames["node_position"][k] - model.node_rest_position
                stamp = frames[frame_stamp(frames)][k]
                cell_data = {}
                for key, parts in XDMF_CELL_FIELDS.items():
                    if key not in frames:
                        continue
                    value = np.asarray(frames[key][k], dtype=np.float64)
                    if parts is None:
                        cell_data[key] = [value]
                    else:
                        cell_data.update({p: [value[:, i]] for i, p in enumerate(parts)})
                writer.write_data(float(stamp),
                                  point_data={"displacement": disp,
                                              "fixed": model.node_fixed.astype(np.float64)},
                                  cell_data=cell_data)
    finally:
        os.chdir(cwd)


RESULT_ATTRS = ("procedure", "scene")
"""The attributes every ``result.h5`` carries: what tells a result from another HDF5 file."""


def read_result(path) -> dict:
    """Read ``result.h5`` (a file or the run folder) into {"attrs", "membrane", groups...};
    ValueError naming the file when it is HDF5 but not a result (no :data:`RESULT_ATTRS`,
    or a top-level item that is not a group of datasets), OSError when it is not HDF5."""
    path = Path(path)
    if path.is_dir():
        path = path / RESULT_FILE
    if not path.is_file():
        raise FileNotFoundError(f"no result file at '{path}'")
    out: dict = {}
    with h5py.File(path, "r") as f:
        missing = [k for k in RESULT_ATTRS if k not in f.attrs]
        if missing:
            raise ValueError(f"'{path}' is not a result file: no {', '.join(missing)} "
                             f"attribute")
        out["attrs"] = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in f.attrs.items()}
        for name, grp in f.items():
            if not isinstance(grp, h5py.Group) or \
                    not all(isinstance(ds, h5py.Dataset) for ds in grp.values()):
                raise ValueError(f"'{path}' is not a result file: '{name}' is not a group of "
                                 f"datasets")
            out[name] = {k: _read_dataset(ds) for k, ds in grp.items()}
    return out
