"""``slosh.surface = "linear"``: the limp diaphragm linearised, i.e. linear slosh theory's
free surface.

The liquid keeps its rest region under the level z0; the surface's small elevation eta is a
field on that level, raised by the liquid's normal velocity and felt as the hydrostatic
pressure rho g eta there (:mod:`fluid.linear_surface`). It is the model of the closed forms
(Budiansky's sphere, Lamb's cylinder): nothing changes cell layer, so the inviscid decay keeps
its energy, and the surface's amplitude does not enter. Needs ``fluid.convection = "none"``
(linear theory has no convective term).

* Per window, beside the liquid's measures: the surface's gravitational potential energy
  1/2 rho g sum A_s eta_s^2 (J) over its faces (:func:`fluid.linear_surface.surface_energy`).
* Frames: ``surface_height`` (m) z0 + eta over the height surface's nodes (the columns
  without a surface face take their neighbours' mean).
"""
from __future__ import annotations

from fluid.linear_surface import column_heights, surface_energy

from fsi.lifecycle import Run
from fsi.registry import SceneError
from fsi.procedures.slosh_limp import LimpWindows
from fsi.procedures.slosh_surfaces import register_surface


@register_surface("linear")
class LinearWindows(LimpWindows):
    """The linearised limp diaphragm's windows (module doc): one ``free-linear`` liquid step
    per window under the fixed level."""

    interface_condition = "free-linear"

    @classmethod
    def check(cls, scene) -> None:
        super().check(scene)
        convection = scene["fluid"]["convection"]
        if convection != "none":
            raise SceneError(f"scene key 'fluid.convection' = {convection!r}: slosh.surface = "
                             "'linear' is linear theory; allowed 'none'")

    def potential_energy(self) -> float:
        return surface_energy(self.model, self.fluid.state)

    def step(self, run: Run) -> None:
        k, window = self.k, self.window
        t = (k + 1) * window
        self.fluid.advance(window)
        self.heights = self.level + self.surface.node_rates(
            *column_heights(self.model, self.fluid.state))
        self.sample(run, t)
        self.k += 1
        if run.frame_due(k + 1):
            run.record("frames", dict(time=t, surface_height=self.heights.copy()))
        energy = run.groups["windows"][-1]["potential_energy"]
        run.progress(k + 1, f"t = {t:.3f} s, surface energy {energy:.3e} J")
