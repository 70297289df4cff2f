"""The incompressibility dilemma and its cure on the liquid column of
:mod:`cases.volume_constraint` (Kuettler, Foerster & Wall 2006): the coupling with and without
the volume constraint on the structure side.

    python benchmarks/volume_constraint.py [--smoke]

Prints one JSON object: iterations per window and the outcome of both couplings for several
bulk moduli (the coupling without the constraint also as a list of rows,
``unconstrained_table``), and the level error against the monolithic (KKT) solution (a full run also writes
it to ``docs/data/volume_constraint.json``). ``--smoke``: one bulk modulus,
:data:`SMOKE_BULK_MODULI`.
"""
from __future__ import annotations

import argparse

from _report import SMOKE_HELP, emit
from cases.volume_constraint import WATER_BULK_MODULUS, Column, Lid, couple, monolithic

#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("constrained", "unconstrained", "unconstrained_table")
#: bulk moduli (Pa) of a full run and of --smoke
BULK_MODULI = (1e3, 1e5, WATER_BULK_MODULUS)
SMOKE_BULK_MODULI = (1e5,)


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    out = {"constrained": {}, "unconstrained": {}, "unconstrained_table": []}
    lid, column = Lid(), Column()
    for bulk in (SMOKE_BULK_MODULI if args.smoke else BULK_MODULI):
        log, err, data = couple(True, bulk)
        w_ref, level_ref = monolithic(lid, column, 0.4, 0.1)
        out["constrained"][f"B={bulk:.3g}"] = dict(
            iterations=[w.iterations for w in log.windows],
            level_relative_error=abs(float(data["pressure_level"][0]) - level_ref) / abs(level_ref),
            volume_error=abs(lid.h * data["displacement"].sum() - column.target(0.4, 0.1)))
        row = {}
        for acc, omega in (("constant", 1.0), ("constant", 0.5), ("aitken", 0.5), ("iqn-ils", 0.5)):
            log, err, _ = couple(False, bulk, acc, omega)
            row[f"{acc} omega0={omega}"] = (
                {"mean_iterations": log.mean_iterations} if log else {"diverged": err})
            out["unconstrained_table"].append(dict(
                bulk_modulus=bulk, acceleration=acc, omega0=omega,
                mean_iterations=log.mean_iterations if log else None,
                outcome="converged" if log else "diverged"))
        out["unconstrained"][f"B={bulk:.3g}"] = row
    emit("volume_constraint", out, args.smoke)
    return out


if __name__ == "__main__":
    main()
