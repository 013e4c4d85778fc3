"""HDF5 superelement files (h5py): every field, reproducible byte for byte.

Layout: root attributes ``format = "flexarm-superelement"``, ``version``, ``units``,
``coupling``, ``method``, ``input_hash``, ``dofs_per_node``, ``mass``; one root dataset
per array field (``K``, ``M``, ``T``, ``interface_names`` as fixed-length UTF-8 bytes,
...), and the root attribute ``checksum``, the SHA-256 of the content
(:mod:`~flexarm.reduction.formats._checksum`), verified on reading.  No timestamps:
datasets are created with ``track_times=False``, the file has a
fixed ``libver`` and attributes are written in a fixed order, so identical inputs give
identical bytes.  MATLAB (``h5read``), Julia (HDF5.jl) and any HDF5 tool read it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...fe.errors import ReadError
from ...fe.files import atomic_path
from ..superelement import SCALAR_FIELDS, Superelement, from_arrays, to_arrays
from ._checksum import CHECKSUM_KEY, content_checksum, verify_checksum

__all__ = ["read", "write", "MAGIC"]

MAGIC = "flexarm-superelement"


def write(path, se: Superelement) -> None:
    """Write ``se`` to ``path`` (.h5) atomically."""
    import h5py

    data = to_arrays(se)
    checksum = content_checksum(data)
    with atomic_path(path) as tmp:
        with h5py.File(tmp, "w", libver=("v110", "v110"), track_order=True) as f:
            f.attrs["format"] = MAGIC
            f.attrs[CHECKSUM_KEY] = checksum
            for key in sorted(SCALAR_FIELDS):
                f.attrs[key] = data.pop(key)
            names = data.pop("interface_names")
            f.create_dataset("interface_names", data=np.array([s.encode() for s in names],
                                                              dtype="S"), track_times=False)
            for key in sorted(data):
                f.create_dataset(key, data=np.asarray(data[key]), track_times=False)


def read(path) -> Superelement:
    """Read and check a superelement written by :func:`write`."""
    import h5py

    path = Path(path)
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise ReadError(f"{path}: not an HDF5 file ({exc})") from None
    with f:
        if f.attrs.get("format") != MAGIC:
            raise ReadError(f"{path}: not a flexarm superelement (format attribute missing)")
        stored = f.attrs.get(CHECKSUM_KEY)
        # the superelement's own attributes: others (a build's statistics added by the
        # cache) are not part of its content
        d = {k: f.attrs[k] for k in f.attrs if k in SCALAR_FIELDS}
        try:
            for key in f:
                d[key] = f[key][()]
        except OSError as exc:  # a truncated file opens but its data cannot be read
            raise ReadError(f"{path}: damaged HDF5 data ({exc})") from None
    if "interface_names" in d:
        d["interface_names"] = [s.decode() for s in d["interface_names"]]
    verify_checksum(d, stored, path)
    return from_arrays(d, str(path))
