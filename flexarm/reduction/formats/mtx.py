"""Matrix Market bundle: a folder ``NAME.mtx/`` with ``K.mtx``, ``M.mtx`` and
``superelement.json`` (interfaces, frames, frequencies, mass properties, hash).

Each matrix is written as ``coordinate real general``: every non-zero entry of both
triangles, at full double precision (the shortest decimal that reads back to the same
float64).  That is the one form every reader takes as it is: Eigen's ``loadMarket``
ignores the symmetry in the header (a ``symmetric`` file comes back as its lower
triangle) and returns an empty matrix for the dense ``array`` form; MATLAB's and SciPy's
``mmread`` and Julia's MatrixMarket.jl read it as well.  The bundle folder and its files
get the permissions the umask gives.  The recovery matrix and surface mesh are not part
of this export.
``superelement.json`` also holds the ``checksum`` of the content as read back (the two
matrices and the metadata, :mod:`~flexarm.reduction.formats._checksum`), verified on
reading.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

import numpy as np
import scipy.io
import scipy.sparse as sp

from ...fe.errors import ReadError
from ...fe.files import umask_mode
from ..superelement import Superelement, from_arrays
from ._checksum import CHECKSUM_KEY, content_checksum, verify_checksum
from ._meta import meta_from_json, meta_json

__all__ = ["read", "write"]


def write(path, se: Superelement) -> None:
    """Write the bundle folder ``path`` atomically (replacing an existing bundle)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.", dir=path.parent))
    try:
        for name in ("K", "M"):
            # "general": with symmetry=None SciPy would find the symmetry and keep one triangle
            scipy.io.mmwrite(tmp / f"{name}.mtx", sp.coo_matrix(np.asarray(getattr(se, name))),
                             comment=f"flexarm superelement {name} (SI units)",
                             symmetry="general")
        # the checksum is of what a reader gets back from the text just written
        d = meta_from_json(meta_json(se))
        d.update(_matrices(tmp, tmp))
        (tmp / "superelement.json").write_text(meta_json(se, content_checksum(d)) + "\n")
        os.chmod(tmp, umask_mode(0o777))  # mkdtemp made it private
        if path.is_dir() and (path / "superelement.json").exists():
            shutil.rmtree(path)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            shutil.rmtree(tmp)


def read(path) -> Superelement:
    """Read a bundle written by :func:`write`."""
    path = Path(path)
    meta = path / "superelement.json"
    if not path.is_dir() or not meta.exists():
        raise ReadError(f"{path}: not a Matrix Market superelement folder "
                        "(needs K.mtx, M.mtx, superelement.json)")
    d = meta_from_json(meta.read_text())
    stored = d.pop(CHECKSUM_KEY, None)
    d.update(_matrices(path, path))
    verify_checksum(d, stored, path)
    return from_arrays(d, str(path))


def _matrices(folder: Path, name_for_errors: Path) -> dict:
    """``K`` and ``M`` (dense float64) from ``folder``'s ``K.mtx`` and ``M.mtx``."""
    out = {}
    for name in ("K", "M"):
        f = folder / f"{name}.mtx"
        if not f.exists():
            raise ReadError(f"{name_for_errors}: missing {name}.mtx")
        try:
            A = scipy.io.mmread(f)
        except (ValueError, OSError) as exc:
            raise ReadError(f"{f}: not a Matrix Market file ({exc})") from None
        out[name] = np.asarray(A.toarray() if hasattr(A, "toarray") else A, dtype=np.float64)
    return out
