"""Reduction layer: interface regions -> RBE2/RBE3 couplings -> Guyan / Craig-Bampton
-> :class:`Superelement` -> files (HDF5, NPZ, Matrix Market, Nastran DMIG).

Imports only :mod:`flexarm.fe`.
"""

from . import formats
from .couplings import COUPLINGS, Coupling, couple, farthest_points, tributary_areas
from .craig_bampton import craig_bampton, craig_bampton_basis
from .guyan import Reduction, constraint_modes, guyan, guyan_basis
from .interfaces import (
    CylinderRegion,
    Interface,
    NodeSetRegion,
    axis_frame,
    interfaces,
    parse_cylinder,
    select_region,
)
from .projection import project
from .recovery import mode_shape, static_deflection
from .reduce import (
    METHODS,
    CoupledModel,
    ReductionStats,
    coupled_model,
    reduce_part,
    reduce_with_stats,
)
from .superelement import (
    FORMAT_VERSION,
    Superelement,
    matrix_mass_properties,
    reduced_rigid_modes,
)

__all__ = [
    "CylinderRegion", "NodeSetRegion", "Interface", "interfaces", "select_region",
    "parse_cylinder", "axis_frame",
    "Coupling", "couple", "COUPLINGS", "tributary_areas", "farthest_points",
    "project", "Reduction", "guyan", "guyan_basis", "constraint_modes",
    "craig_bampton", "craig_bampton_basis",
    "CoupledModel", "ReductionStats", "coupled_model", "reduce_part", "reduce_with_stats",
    "METHODS",
    "Superelement", "FORMAT_VERSION", "reduced_rigid_modes", "matrix_mass_properties",
    "mode_shape", "static_deflection", "formats",
]
