"""Volume-mesh file formats, one module each, found by extension through ``_registry``."""

from . import msh, npz, vtk, vtu
from ._registry import VolumeFormat, extensions, format_for, register_format

__all__ = [
    "VolumeFormat",
    "extensions",
    "format_for",
    "register_format",
    "msh",
    "npz",
    "vtk",
    "vtu",
]
