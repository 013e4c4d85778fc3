"""Superelement file formats, one module each, registered by extension."""

from . import dmig, h5, mtx, npz
from ._registry import EXTENSIONS, FORMATS, format_of, read, register_format, write

register_format("h5", (".h5", ".hdf5", ".se"), h5)
register_format("npz", (".npz",), npz)
register_format("mtx", (".mtx",), mtx)
register_format("dmig", (".bdf", ".dmig", ".pch", ".dat"), dmig)

__all__ = ["read", "write", "format_of", "register_format", "FORMATS", "EXTENSIONS"]
