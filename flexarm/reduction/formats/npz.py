"""NumPy ``.npz`` superelement files (every field; ``numpy.load`` reads them)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...fe.errors import ReadError
from ...fe.files import atomic_path
from ..superelement import Superelement, from_arrays, to_arrays

__all__ = ["read", "write"]


def write(path, se: Superelement) -> None:
    """Write ``se`` to ``path`` (.npz) atomically; strings become unicode arrays."""
    data = {k: np.asarray(v) for k, v in to_arrays(se).items()}
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        np.savez(f, **data)


def read(path) -> Superelement:
    """Read and check a superelement written by :func:`write` (no pickles)."""
    path = Path(path)
    try:
        with np.load(path, allow_pickle=False) as z:
            d = {k: z[k] for k in z.files}
    except (OSError, ValueError) as exc:
        raise ReadError(f"{path}: not a NumPy .npz file ({exc})") from None
    if "interface_names" in d:
        d["interface_names"] = [str(s) for s in d["interface_names"]]
    return from_arrays(d, str(path))
