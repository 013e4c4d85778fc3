"""Volume-mesh file formats, one module each, found by extension through ``registry``."""

from ...fe.formats import FormatRegistry
from . import msh, npz, vtk, vtu

#: The volume-mesh formats (:class:`~flexarm.fe.formats.FormatRegistry`).
registry = FormatRegistry("volume mesh")
registry.register("gmsh", (".msh",), msh.read, msh.write)
registry.register("npz", (".npz",), npz.read, npz.write)
registry.register("vtk", (".vtk",), vtk.read, vtk.write)
registry.register("vtu", (".vtu",), vtu.read, vtu.write)

__all__ = ["registry", "msh", "npz", "vtk", "vtu"]
