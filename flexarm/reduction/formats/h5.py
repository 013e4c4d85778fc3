"""HDF5 superelement files (h5py): every field, reproducible byte for byte.

Layout: root attributes ``format = "flexarm-superelement"``, ``version``, ``units``,
``coupling``, ``method``, ``input_hash``, ``dofs_per_node``, ``mass``; one root dataset
per array field (``K``, ``M``, ``T``, ``interface_names`` as fixed-length UTF-8 bytes,
...).  No timestamps: datasets are created with ``track_times=False``, the file has a
fixed ``libver`` and attributes are written in a fixed order, so identical inputs give
identical bytes.  MATLAB (``h5read``), Julia (HDF5.jl) and any HDF5 tool read it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...fe.errors import ReadError
from ...fe.files import atomic_path
from ..superelement import SCALAR_FIELDS, Superelement, from_arrays, to_arrays

__all__ = ["read", "write", "MAGIC"]

MAGIC = "flexarm-superelement"


def write(path, se: Superelement) -> None:
    """Write ``se`` to ``path`` (.h5) atomically."""
    import h5py

    data = to_arrays(se)
    with atomic_path(path) as tmp:
        with h5py.File(tmp, "w", libver=("v110", "v110"), track_order=True) as f:
            f.attrs["format"] = MAGIC
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
        d = {k: f.attrs[k] for k in f.attrs if k != "format"}
        for key in f:
            d[key] = f[key][()]
    if "interface_names" in d:
        d["interface_names"] = [s.decode() for s in d["interface_names"]]
    return from_arrays(d, str(path))
