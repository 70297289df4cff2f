"""Building a run from a scene: the structure-model registry, Courant limits, the fill scale, carried starts, tank motion."""
