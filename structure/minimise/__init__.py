"""Statics as constrained minimisation: the membrane's potential with the tank wall as a
smooth barrier (:mod:`structure.minimise.barrier`), minimised by projected Newton with the
pressure level the volume's multiplier (:mod:`structure.minimise.newton`), along the fill
path by adaptive volume steps (:mod:`structure.minimise.path`); the potential built from a
membrane model in :mod:`structure.minimise.model`."""
from .barrier import BarrierWall
from .model import (DHAT, RESIDUAL_STIFFNESS, inside, membrane_terms, minimisation_model,
                    xpbd_terms)
from .newton import MinimiseSettings
from .path import PathReport, fill_path

__all__ = ["BarrierWall", "DHAT", "RESIDUAL_STIFFNESS", "MinimiseSettings", "PathReport",
           "fill_path", "inside", "membrane_terms", "minimisation_model", "xpbd_terms"]
