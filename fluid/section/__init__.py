"""The liquid on the tank's meridional section: isoparametric P2 meshes of the section
(:mod:`~fluid.section.mesh`) and the potential flow of one circumferential harmonic on them
(:mod:`~fluid.section.potential`), with scikit-fem."""
