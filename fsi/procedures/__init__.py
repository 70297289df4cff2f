"""The procedures a scene can run, one module each, registered in :data:`PROCEDURES`
(:mod:`fsi.registry`): ``volume-sweep``, ``thesis-ramp`` and ``coupled-fill``.

Importing this package registers them all. A new procedure is a new module here, imported
below, that calls :func:`fsi.registry.register_procedure` with its record.
"""
from ..lifecycle import RunResult
from ..registry import PROCEDURES, Procedure
from . import volume_sweep  # noqa: F401,E402  (each import registers one procedure)
from . import thesis_ramp  # noqa: F401,E402
from . import coupled_fill  # noqa: F401,E402

__all__ = ["PROCEDURES", "Procedure", "RunResult"]
