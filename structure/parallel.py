"""Independent pieces of one run on the machine's cores: a map over processes.

The stability tables of a fill's states, or the slosh modes at its fills, are independent of
one another; :func:`process_map` spreads them over worker processes (forked, so the caller's
modules and data are there already; results come back pickled, in order). Each worker runs
NumPy's BLAS on one thread: with a thread per core in every worker the threads wait on each
other (``docs/notes/blas-threads.md``). Where fork is not available, one worker is asked
for, or the caller is itself a daemonic worker (a Dask sweep's, which may not start
processes), the map runs in the calling process.
"""
from __future__ import annotations

import multiprocessing
import os
from concurrent.futures import ProcessPoolExecutor
from typing import Callable, Iterable, Optional

__all__ = ["WORKERS", "process_map"]

WORKERS = max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity")
              else (os.cpu_count() or 1))
"""The worker processes of a map by default: the cores this process may run on."""


def _one_blas_thread() -> None:
    from threadpoolctl import threadpool_limits
    threadpool_limits(1)


def process_map(function: Callable, items: Iterable, workers: Optional[int] = None) -> list:
    """[function(item) for item in items], over ``workers`` processes (:data:`WORKERS` by
    default; 1 runs here). ``function`` and the items must pickle (a module-level function,
    or a :func:`functools.partial` of one)."""
    items = list(items)
    count = min(WORKERS if workers is None else int(workers), len(items))
    if count <= 1 or "fork" not in multiprocessing.get_all_start_methods() \
            or multiprocessing.current_process().daemon:
        return [function(item) for item in items]
    context = multiprocessing.get_context("fork")
    with ProcessPoolExecutor(count, mp_context=context, initializer=_one_blas_thread) as pool:
        return list(pool.map(function, items))
