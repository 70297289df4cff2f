"""A sweep's combined dataset: every case's scalar results indexed by the swept keys, as an
xarray Dataset in DIR/sweep.nc (netCDF-4, written through h5netcdf), and its plots.

Dimensions are the sweep's axes (:class:`fsi.sweep.file.Axis`): one per ``[vary]`` key, named
by the key, whose coordinate is its values; one per ``[zip.NAME]`` table, named NAME, with a
coordinate per key. Variables (one value per case, NaN where a case has none):

* every scalar run fact of the case's ``result.h5`` (its attributes: e.g. ``lambda1``,
  ``zeta``, ``slosh_mass``, ``tank_fraction``, ``run_seconds``), true/false as 1/0, with
  ``units``;
* ``exit_status``: the case's ``fsi run`` exit status (0 converged, 1 stopped, 2 bad input,
  3 not everything converged; -1 its worker died or it raised; -2 not run);
* ``failure``: the reason a case stopped or failed ('' when none).

For cases that record frames at requested fills (a ``volume-sweep``'s filling leg), a
dimension ``fill`` (the requested fills, on the run's ``fill_scale``) and, per case and fill,
``fill_tank_fraction``, ``fill_pressure_level``, ``fill_equivalent_height``,
``fill_strain_error``, ``fill_converged`` and ``fill_wall_seconds`` (the frames' datasets,
docs/user-guide/outputs.md); with ``sweep.reference``, ``fill_shape_error`` (Eqn 6.1 %, the
case's shape against the reference case's frame nearest in tank fraction) and its mean over the
fills, ``shape_error``.

Vector-valued keys' coordinates are written as text ('0.5x0x0').
"""
from __future__ import annotations

import logging
import math
from numbers import Number
from pathlib import Path

import numpy as np

from fsi.analysis.compare import eqn_6_1_error
from fsi.io.output import read_result, software_version, units_of
from fsi.sweep.file import Sweep
from fsi.sweep.run import CASES_DIR, case_records, finished

log = logging.getLogger(__name__)

DATASET_FILE = "sweep.nc"
PLOTS_DIR = "plots"
NOT_RUN = -2
FILL_QUANTITIES = ("tank_fraction", "pressure_level", "equivalent_height", "strain_error",
                   "converged", "wall_seconds")
"""Frame datasets of a run's filling leg gathered per requested fill (``fill_NAME``)."""


def scalars(attrs: dict) -> dict:
    """The numeric scalar entries of ``attrs`` (bool as 0/1) as floats."""
    out = {}
    for key, value in attrs.items():
        if isinstance(value, np.ndarray) and value.ndim == 0:
            value = value.item()
        if isinstance(value, (bool, np.bool_)):
            out[key] = float(value)
        elif isinstance(value, Number) and not isinstance(value, complex):
            out[key] = float(value)
    return out


def key_doc(key: str) -> str:
    """The scene key reference's text of ``key`` ('section.name'; units in it)."""
    from fsi.scene import SCHEMA

    section, _, name = key.partition(".")
    return SCHEMA[section][name].doc


def _coordinate(values: list):
    return [("x".join(f"{x:g}" for x in v) if isinstance(v, list) else v) for v in values]


def collect(sweep: Sweep, out) -> "xarray.Dataset":
    """The combined dataset of the sweep in ``out`` (module doc)."""
    import xarray as xr

    out = Path(out)
    records = case_records(out)
    facts, status, failure = {}, np.full(sweep.shape, NOT_RUN), np.full(sweep.shape, "",
                                                                        dtype=object)
    results = {}
    for case in sweep.cases:
        record = records.get(case.name, {})
        status[case.index] = record.get("status", NOT_RUN)
        failure[case.index] = record.get("reason", "")
        if finished(out, case):
            results[case.name] = read_result(out / CASES_DIR / case.name)
            attrs = results[case.name]["attrs"]
            facts[case.name] = scalars(attrs)
            failure[case.index] = attrs.get("failure") or failure[case.index]
    dims = [a.name for a in sweep.axes]
    names = sorted({k for f in facts.values() for k in f})
    data = {}
    for name in names:
        values = np.full(sweep.shape, np.nan)
        for case in sweep.cases:
            values[case.index] = facts.get(case.name, {}).get(name, math.nan)
        data[name] = (dims, values, {"units": units_of(name)})
    data["exit_status"] = (dims, status, {"units": "1"})
    data["failure"] = (dims, failure.astype(str), {"units": ""})
    coords = {key: ([a.name], _coordinate(values), {"description": key_doc(key)})
              for a in sweep.axes for key, values in a.values.items()}
    fills, by_fill = fill_variables(sweep, results)
    if fills is not None:
        scale = {str(r["attrs"].get("fill_scale", "")) for r in results.values()} - {""}
        scale = " ".join(sorted(scale))
        coords["fill"] = (["fill"], fills, {"units": "1", "fill_scale": scale,
                                            "description": f"requested fill ({scale} scale)"})
        data.update(by_fill)
    return xr.Dataset(data, coords=coords, attrs=dict(
        sweep=sweep.name, description=sweep.description, base_scene=sweep.scene,
        sweep_file=sweep.text, software_version=software_version(),
        fill_scale="tank fraction V / (4/3 pi R^3) where a key or result says fill"))


def fill_variables(sweep: Sweep, results: dict) -> tuple:
    """(the requested fills, {fill_NAME: (dims, values, attrs)}) of the cases in ``results``
    ({case name: read_result}) that record ``frames/target_fill``; (None, {}) when
    none does. Dimensions ``("fill", *axes)``, NaN where a case has no frame at a fill."""
    framed = {n: r["frames"] for n, r in results.items()
              if "target_fill" in r.get("frames", {})}
    if not framed:
        return None, {}
    # a frame recorded between requested fills (a coupled run's periodic frames) has none: NaN
    fills = sorted({round(float(f), 12) for fr in framed.values()
                    for f in fr["target_fill"] if np.isfinite(f)})
    if not fills:
        return None, {}
    dims = ["fill"] + [a.name for a in sweep.axes]
    names = list(FILL_QUANTITIES) + (["shape_error"] if sweep.reference in framed else [])
    values = {n: np.full((len(fills),) + sweep.shape, np.nan) for n in names}
    for case in (c for c in sweep.cases if c.name in framed):
        frames = framed[case.name]
        for k, target in enumerate(frames["target_fill"]):
            if not np.isfinite(target):
                continue
            i = fills.index(round(float(target), 12))
            for name in FILL_QUANTITIES:
                if name in frames:
                    values[name][(i,) + case.index] = float(frames[name][k])
            if "shape_error" in values:
                values["shape_error"][(i,) + case.index] = shape_error(
                    results[sweep.reference], results[case.name], k)
    data = {f"fill_{n}": (dims, v, {"units": "%" if n == "shape_error" else units_of(n)})
            for n, v in values.items()}
    if "shape_error" in values:
        data["shape_error"] = (dims[1:], np.nanmean(values["shape_error"], axis=0)
                               if len(fills) else values["shape_error"][0], {"units": "%"})
    return fills, data


def shape_error(reference: dict, result: dict, frame: int) -> float:
    """Eqn 6.1 (%) of ``result``'s shape at ``frame`` against ``reference``'s frame nearest
    in tank fraction (:func:`fsi.analysis.compare.eqn_6_1_error`)."""
    tank = result["frames"]["tank_fraction"][frame]
    j = int(np.argmin(np.abs(reference["frames"]["tank_fraction"] - tank)))
    return eqn_6_1_error(reference["frames"]["node_position"][j],
                         reference["membrane"]["face_nodes"],
                         result["frames"]["node_position"][frame],
                         float(reference["attrs"]["radius"]))


def write(dataset, out) -> Path:
    """Write ``dataset`` to DIR/sweep.nc (netCDF-4 through h5netcdf), atomically."""
    path = Path(out) / DATASET_FILE
    tmp = path.with_name(path.name + ".tmp")
    dataset.to_netcdf(tmp, engine="h5netcdf")
    tmp.replace(path)
    return path


def read(out) -> "xarray.Dataset":
    """The dataset a sweep wrote in ``out`` (loaded, the file closed)."""
    import xarray as xr

    with xr.open_dataset(Path(out) / DATASET_FILE, engine="h5netcdf") as ds:
        return ds.load()


def plot(dataset, names: list[str], out) -> list[Path]:
    """One PNG per quantity in ``names`` against the sweep's first axis, a line for each
    combination of the others, in DIR/plots; a name the dataset lacks is skipped with a
    warning."""
    import itertools

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    folder = Path(out) / PLOTS_DIR
    folder.mkdir(exist_ok=True)
    written = []
    for name in (n for n in names if n not in dataset):
        log.warning("sweep.plot: '%s' is not a quantity of this sweep's dataset; not plotted",
                    name)
    for name in (n for n in names if n in dataset):
        var = dataset[name]
        x_dim, others = var.dims[0], list(var.dims[1:])
        table = var.transpose(x_dim, *others).values.reshape(var.sizes[x_dim], -1)
        combos = list(itertools.product(*(range(var.sizes[d]) for d in others)))
        fig, ax = plt.subplots(figsize=(6, 4))
        for column, combo in enumerate(combos):
            label = ", ".join(_label(dataset, d, i) for d, i in zip(others, combo))
            ax.plot(_axis_values(dataset, x_dim), table[:, column], "o-", label=label or None)
        if not _numeric_coordinates(dataset, x_dim):  # categories: name each position
            ax.set_xticks(range(var.sizes[x_dim]),
                          [_label(dataset, x_dim, i) for i in range(var.sizes[x_dim])])
        units = var.attrs.get("units", "")
        ax.set_xlabel(_axis_title(dataset, x_dim))
        ax.set_ylabel(f"{name} ({units})" if units not in ("", "1") else name)
        ax.set_title(f"{dataset.attrs.get('sweep', '')}: {name}")
        if others:
            ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
        fig.tight_layout()
        fig.savefig(folder / f"{name}.png", dpi=110)
        plt.close(fig)
        written.append(folder / f"{name}.png")
    return written


def _coords_of(dataset, dim: str) -> list[str]:
    return [c for c in dataset.coords if dataset[c].dims == (dim,)]


def _numeric_coordinates(dataset, dim: str) -> list[str]:
    return [c for c in _coords_of(dataset, dim) if np.issubdtype(dataset[c].dtype, np.number)]


def _axis_values(dataset, dim: str):
    """The first numeric coordinate along ``dim``, else the positions 0, 1, ..."""
    numeric = _numeric_coordinates(dataset, dim)
    return dataset[numeric[0]].values if numeric else np.arange(dataset.sizes[dim])


AXIS_TITLE_CHARACTERS = 60
"""A key's description in an axis title is cut at its first ';' and at this length."""


def _axis_title(dataset, dim: str) -> str:
    """The coordinates along ``dim`` with what they are: 'slosh.fill: tank fraction ...'."""
    def title(c):
        text = dataset[c].attrs.get("description", "").split(";")[0]
        if len(text) > AXIS_TITLE_CHARACTERS:
            text = text[:AXIS_TITLE_CHARACTERS - 3].rstrip() + "..."
        return f"{c}: {text}" if text else c

    return " / ".join(title(c) for c in _coords_of(dataset, dim) or [dim])


def _label(dataset, dim: str, index: int | None = None) -> str:
    """The coordinates along ``dim`` ('a / b'), or their values at ``index`` ('a=1, b=x')."""
    coords = _coords_of(dataset, dim) or [dim]
    if index is None:
        return " / ".join(coords)
    return ", ".join(f"{c}={dataset[c].values[index] if c in dataset.coords else index}"
                     for c in coords)
