"""``structure.parallel.process_map``: the same results, in order, over worker processes as in
the calling process; and the shell of revolution's stability tables spread over workers are
the serial ones."""
from __future__ import annotations

import os
from functools import partial

import numpy as np

from structure.parallel import process_map


def _square_and_pid(offset, x):
    return x * x + offset, os.getpid()


def test_process_map_keeps_the_order_and_runs_elsewhere():
    items = list(range(7))
    serial = process_map(partial(_square_and_pid, 1), items, workers=1)
    spread = process_map(partial(_square_and_pid, 1), items, workers=2)
    assert [v for v, _ in serial] == [v for v, _ in spread] == [x * x + 1 for x in items]
    assert {p for _, p in serial} == {os.getpid()}
    assert os.getpid() not in {p for _, p in spread}
    assert process_map(partial(_square_and_pid, 0), [], workers=2) == []


def test_stability_tables_over_two_workers_are_the_serial_ones():
    from fsi.constants import (MEMBRANE_DENSITY, MEMBRANE_THICKNESS, MEMBRANE_YOUNGS_MODULUS,
                               STANDARD_GRAVITY, TANK_RADIUS, WATER_DENSITY)
    from structure.axisymmetric import AxisymmetricLoad, law_of, shell_of_revolution
    from structure.axisymmetric.folding import stability_tables
    from structure.axisymmetric.solve import equilibrium
    from structure.model import Material
    material = Material(MEMBRANE_THICKNESS, MEMBRANE_DENSITY, MEMBRANE_YOUNGS_MODULUS, 0.5)
    shell = shell_of_revolution("hemisphere", TANK_RADIUS, material,
                                law_of(material, "neo-hookean"), 16, rim_ratio=0.3)
    load = AxisymmetricLoad(liquid_density=WATER_DENSITY, gravity=STANDARD_GRAVITY,
                            pressure=-500.0)
    rest = equilibrium(shell, load)
    pushed = equilibrium(shell, AxisymmetricLoad(liquid_density=WATER_DENSITY,
                                                 gravity=STANDARD_GRAVITY, pressure=-1500.0),
                         rest.state)
    results = [rest, None, pushed]
    serial = stability_tables(shell, load, results, range(1, 9), workers=1)
    spread = stability_tables(shell, load, results, range(1, 9), workers=2)
    assert serial[1] is None and spread[1] is None
    for a, b in zip(serial[::2], spread[::2]):
        assert np.allclose(a.eigenvalue, b.eigenvalue, rtol=1e-8)
        assert list(a.negative) == list(b.negative)


def test_a_daemonic_worker_maps_in_its_own_process():
    """A daemonic process (a Dask sweep's worker) may not start processes: the map runs
    there."""
    import multiprocessing
    context = multiprocessing.get_context("fork")
    queue = context.Queue()
    worker = context.Process(target=_map_and_report, args=(queue,), daemon=True)
    worker.start()
    worker.join(60)
    values, pids, own = queue.get(timeout=5)
    assert values == [1, 2, 5] and pids == {own}


def _map_and_report(queue):
    out = process_map(partial(_square_and_pid, 1), [0, 1, 2], workers=2)
    queue.put(([v for v, _ in out], {p for _, p in out}, os.getpid()))
