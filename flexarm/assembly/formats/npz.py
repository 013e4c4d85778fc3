"""State-space models as NumPy ``.npz`` (``numpy.load`` reads them; no pickles)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...fe.errors import ReadError
from ...fe.files import atomic_path, write_npz
from ..state_space import ArmStateSpace, from_arrays, to_arrays

__all__ = ["read", "write"]


def write(path, ss: ArmStateSpace) -> None:
    """Write ``ss`` to ``path`` (.npz) atomically; names become unicode arrays."""
    data = {k: np.asarray(v) for k, v in to_arrays(ss).items()}
    with atomic_path(path) as tmp:
        write_npz(tmp, data)


def read(path) -> ArmStateSpace:
    """Read and check a state-space model written by :func:`write`."""
    path = Path(path)
    try:
        with np.load(path, allow_pickle=False) as z:
            d = {k: z[k] for k in z.files}
    except (OSError, ValueError) as exc:
        raise ReadError(f"{path}: not a NumPy .npz file ({exc})") from None
    return from_arrays(d, str(path))
