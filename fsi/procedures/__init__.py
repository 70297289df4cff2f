"""The procedures a scene can run, one module each, registered in :data:`PROCEDURES`
(:mod:`fsi.registry`): ``plate-estimate`` (closed forms), ``volume-sweep`` and
``thesis-ramp`` (static), ``coupled-fill`` and ``slosh`` (dynamic).

Importing this package imports every module in it, and each procedure module registers its
record with :func:`fsi.registry.register_procedure`: a new procedure is a new module here.
Modules that register nothing hold what several procedures share (:mod:`.static`,
:mod:`.coupled`).
"""
import importlib
import pkgutil

from fsi.lifecycle import RunResult
from fsi.registry import PROCEDURES, Procedure

for _module in sorted(m.name for m in pkgutil.iter_modules(__path__)):
    importlib.import_module(f"{__name__}.{_module}")

__all__ = ["PROCEDURES", "Procedure", "RunResult"]
