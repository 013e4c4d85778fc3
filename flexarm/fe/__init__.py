"""Base layer: tetrahedral mesh, elements, sparse assembly, loads, solvers, errors.

Everything above (meshes, reduction, assembly, validation, cli) imports from here;
this package imports nothing of flexarm's.
"""

from .assembly import (
    NodePattern,
    assemble,
    element_mass,
    element_stiffness,
    is_affine,
    mass_matrix,
    stiffness_blocks,
    stiffness_matrix,
)
from .boundary import DofSplit, dof_split, node_dofs
from .eigen import Modes, auto_shift, modes, shift_invert, static_solve
from .errors import (
    ConvergenceError,
    FlexarmError,
    InterfaceError,
    MeshError,
    MissingDependencyError,
    ReadError,
)
from .loads import STANDARD_GRAVITY, gravity_load, nodal_load
from .mass_properties import MassProperties, mass_properties, rigid_body_mass_matrix
from .material import MATERIALS, Material, material_from_string
from .mesh import TET10_EDGES, TET_FACES, TetMesh
from .quadrature import tet_quadrature
from .selection import select_nodes
from .solvers import (
    Factor,
    SingularMatrixError,
    available_backends,
    default_backend,
    factorize,
    set_default_backend,
)
from .tet4 import Tet4
from .tet10 import Tet10
from .tolerances import Tolerances, tol

__all__ = [
    "TetMesh", "TET10_EDGES", "TET_FACES", "Tet4", "Tet10", "tet_quadrature",
    "Material", "MATERIALS", "material_from_string",
    "assemble", "stiffness_matrix", "mass_matrix", "element_stiffness", "element_mass",
    "stiffness_blocks", "is_affine", "NodePattern",
    "DofSplit", "dof_split", "node_dofs", "select_nodes",
    "gravity_load", "nodal_load", "STANDARD_GRAVITY",
    "Modes", "modes", "shift_invert", "auto_shift", "static_solve",
    "Factor", "factorize", "available_backends", "default_backend", "set_default_backend",
    "SingularMatrixError",
    "MassProperties", "mass_properties", "rigid_body_mass_matrix",
    "FlexarmError", "MeshError", "InterfaceError", "ReadError", "ConvergenceError",
    "MissingDependencyError",
    "Tolerances", "tol",
]
