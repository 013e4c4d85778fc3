"""NumPy ``.npz`` superelement files (every field; ``numpy.load`` reads them).

The content checksum (:mod:`~flexarm.reduction.formats._checksum`) is the zip archive's
comment, which ``numpy.load`` and every zip tool ignore; it is verified on reading.
"""

from __future__ import annotations

import zipfile
from pathlib import Path

import numpy as np

from ...fe.errors import ReadError
from ...fe.files import atomic_path, write_npz
from ..superelement import Superelement, from_arrays, to_arrays
from ._checksum import content_checksum, verify_checksum

__all__ = ["read", "write"]

#: Start of the zip comment that holds the checksum.
_TAG = "flexarm-superelement "


def write(path, se: Superelement) -> None:
    """Write ``se`` to ``path`` (.npz) atomically; strings become unicode arrays."""
    data = {k: np.asarray(v) for k, v in to_arrays(se).items()}
    with atomic_path(path) as tmp:
        write_npz(tmp, data, (_TAG + content_checksum(data)).encode())


def read(path) -> Superelement:
    """Read and check a superelement written by :func:`write` (no pickles)."""
    path = Path(path)
    try:
        with np.load(path, allow_pickle=False) as z:
            d = {k: z[k] for k in z.files}
        with zipfile.ZipFile(path) as z:
            comment = z.comment.decode(errors="replace")
    except (OSError, ValueError, zipfile.BadZipFile) as exc:
        raise ReadError(f"{path}: not a NumPy .npz file ({exc})") from None
    stored = comment[len(_TAG):] if comment.startswith(_TAG) else None
    verify_checksum(d, stored, path)
    if "interface_names" in d:
        d["interface_names"] = [str(s) for s in d["interface_names"]]
    return from_arrays(d, str(path))
