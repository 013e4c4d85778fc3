"""Content checksum of a stored superelement, kept as metadata next to the data.

Each format stores the SHA-256 of the *decoded* content (every field as a reader gets
it back) where that format keeps metadata: an HDF5 root attribute, the ``.npz`` zip
comment, a key of ``superelement.json`` (Matrix Market) or of the ``$flexarm-json``
line (DMIG).  The layout of the data is unchanged, so other tools read the files as
before.  On reading, a stored checksum that differs from the content read is a
:class:`~flexarm.fe.errors.ReadError` naming the file: a flipped bit, a truncated or
hand-edited value never turns into a silently different superelement.  Files written
before checksums existed carry none and are read as before.
"""

from __future__ import annotations

import hashlib
from collections.abc import Mapping

import numpy as np

from ...fe.errors import ReadError

__all__ = ["CHECKSUM_KEY", "content_checksum", "verify_checksum"]

#: Name of the checksum in every format's metadata.
CHECKSUM_KEY = "checksum"

_PREFIX = "sha256:"


def _canonical(value) -> tuple[str, bytes]:
    """Type tag and bytes of one field, independent of how the format typed it (an HDF5
    ``int64`` attribute and a JSON integer give the same bytes)."""
    a = np.asarray(value)
    kind = a.dtype.kind
    if kind in "USO":
        return "str", "\x00".join(str(s) for s in a.ravel()).encode()
    if kind == "b":
        return "bool", a.astype(np.uint8).tobytes()
    if kind in "iu":
        return "int", a.astype("<i8").tobytes()
    if kind == "f":
        return "float", a.astype("<f8").tobytes()
    if kind == "c":
        return "complex", a.astype("<c16").tobytes()
    raise TypeError(f"cannot checksum a field of dtype {a.dtype}")


def content_checksum(fields: Mapping) -> str:
    """``"sha256:<hex>"`` of every field in ``fields`` except :data:`CHECKSUM_KEY`.

    Names, shapes and values enter; floats bit for bit as float64.

    Examples
    --------
    >>> a = content_checksum({"K": np.eye(2), "coupling": "rbe2", "dofs_per_node": 6})
    >>> a == content_checksum({"coupling": "rbe2", "dofs_per_node": np.int64(6),
    ...                        "K": [[1.0, 0.0], [0.0, 1.0]]})
    True
    >>> a == content_checksum({"K": np.eye(2) * (1 + 2**-52), "coupling": "rbe2",
    ...                        "dofs_per_node": 6})
    False
    """
    h = hashlib.sha256()
    for key in sorted(k for k in fields if k != CHECKSUM_KEY):
        tag, body = _canonical(fields[key])
        h.update(f"{key}|{tag}|{np.shape(fields[key])}|".encode())
        h.update(body)
        h.update(b"\x00")
    return _PREFIX + h.hexdigest()


def verify_checksum(fields: Mapping, stored, source) -> None:
    """Raise :class:`ReadError` naming ``source`` if ``stored`` (None: no checksum was
    written) is not the checksum of ``fields``.

    Examples
    --------
    >>> d = {"K": np.eye(2)}
    >>> verify_checksum(d, content_checksum(d), "se.h5")
    >>> verify_checksum({"K": np.eye(2) * 2}, content_checksum(d), "se.h5")
    ... # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    flexarm.fe.errors.ReadError: se.h5: checksum mismatch: the content is not what ...
    """
    if stored is None:
        return
    stored = stored.decode() if isinstance(stored, bytes) else str(stored)
    actual = content_checksum(fields)
    if stored != actual:
        raise ReadError(f"{source}: checksum mismatch: the content is not what was written "
                        f"(a damaged or edited file); stored {stored[:15]}..., content "
                        f"{actual[:15]}...")
