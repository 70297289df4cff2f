"""The membrane. Knows nothing of fluids: takes a :class:`structure.load.Load` (node pressure,
body acceleration, volume target or level) and returns positions.

Models share the thesis grid, masses and fixed rings (:mod:`structure.model`); static solves
return (state, :class:`structure.load.Equilibrium`), dynamic steppers share
``step(model, state_in, load, dt, settings) -> (state_out, StepInfo)``
(:func:`structure.thesis.step`, :func:`structure.xpbd.step`).
"""
