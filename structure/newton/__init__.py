"""Newton-class mechanics of the membrane: its residual and tangent stiffness under the
liquid's load (:mod:`.system`), sparse direct solves (:mod:`.linear`), and static equilibrium
by Newton's method with the pressure level as the multiplier of the volume, continued over
fill by pseudo-arc-length (:mod:`.statics`)."""
