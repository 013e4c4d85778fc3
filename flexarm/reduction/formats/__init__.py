"""Superelement file formats, one module each (``read(path)``, ``write(path, se)``),
found by extension or name through ``registry``."""

from ...fe.formats import FormatRegistry
from ..superelement import use_reader
from . import dmig, h5, mtx, npz, op4

#: The superelement formats (:class:`~flexarm.fe.formats.FormatRegistry`).
registry = FormatRegistry("superelement")
registry.register("h5", (".h5", ".hdf5", ".se"), h5.read, h5.write)
registry.register("npz", (".npz",), npz.read, npz.write)
registry.register("mtx", (".mtx",), mtx.read, mtx.write)
registry.register("dmig", (".bdf", ".dmig", ".pch", ".dat"), dmig.read, dmig.write)
registry.register("op4", (".op4",), write=op4.write)  # matrices only: write-only


def _is_mtx_bundle(path) -> bool:
    """A Matrix Market bundle folder (as ``reduce --format mtx`` writes it, any name)."""
    from pathlib import Path

    return Path(path).is_dir() and (Path(path) / "superelement.json").is_file()


def read(path, file_format: str | None = None):
    """Read a superelement; the format follows the extension unless ``file_format`` names it
    (a Matrix Market bundle folder is recognised by its ``superelement.json``, whatever
    its name).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from flexarm.fe import MATERIALS, TetMesh
    >>> from flexarm.reduction import CylinderRegion, reduce_part
    >>> mesh = TetMesh.box((0.4, 0.04, 0.04), (8, 2, 2))
    >>> ends = [CylinderRegion(n, (x, 0.02, 0.02), (1, 0, 0), 0.0, 0.04, 1e-6)
    ...         for n, x in (("a", 0.0), ("b", 0.4))]
    >>> se = reduce_part(mesh, MATERIALS["steel"], ends, "rbe2", "cb", 4)
    >>> path = write(pathlib.Path(tempfile.mkdtemp()) / "bar.h5", se)
    >>> read(path).n_dofs
    16
    """
    if file_format is None and registry.find(path) is None and _is_mtx_bundle(path):
        file_format = "mtx"
    return registry.read(path, file_format)


def convert(source, target, file_format: str | None = None,
            source_format: str | None = None):
    """Rewrite the superelement ``source`` in the format of ``target`` (its extension or
    ``file_format``) without reducing again; returns the target path.

    Everything the target format holds is copied unchanged (HDF5 and NPZ hold every
    field; Matrix Market and DMIG hold the matrices and the interface data, not the
    recovery matrix or the surface mesh).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from flexarm.fe import MATERIALS, TetMesh
    >>> from flexarm.reduction import CylinderRegion, reduce_part
    >>> mesh = TetMesh.box((0.4, 0.04, 0.04), (4, 1, 1))
    >>> ends = [CylinderRegion(n, (x, 0.02, 0.02), (1, 0, 0), 0.0, 0.04, 1e-6)
    ...         for n, x in (("a", 0.0), ("b", 0.4))]
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> h5 = write(d / "bar.h5", reduce_part(mesh, MATERIALS["steel"], ends, "rbe2", "cb", 2))
    >>> bool((read(convert(h5, d / "bar.npz")).K == read(h5).K).all())
    True
    """
    registry.format_of(target, file_format, "w")  # a bad target fails before reading
    return write(target, read(source, source_format), file_format)


def write(path, se, file_format: str | None = None):
    """Write ``se`` to ``path`` (atomically) in the format of its extension or
    ``file_format``; returns the path."""
    return registry.write(path, se, file_format)


def format_of(path, file_format: str | None = None) -> str:
    """Name of the format given explicitly or by the extension of ``path`` (a bad one
    raises ``ValueError`` before any work)."""
    return registry.format_of(path, file_format).name


use_reader(read)  # Superelement.load reads through the same registry

__all__ = ["registry", "read", "write", "format_of", "convert"]
