"""Small-field metadata shared by the matrix-only formats (Matrix Market, DMIG)."""

from __future__ import annotations

import json

import numpy as np

from ..superelement import Superelement, to_arrays
from ._checksum import CHECKSUM_KEY

__all__ = ["META_FIELDS", "meta_json", "meta_from_json"]

#: Everything except the big arrays (K, M, recovery matrix, surface mesh).
META_FIELDS = ("interface_names", "interface_positions", "interface_frames", "coupling",
               "method", "node_positions", "node_interface", "dofs_per_node", "freq_hz",
               "mass", "center_of_mass", "inertia", "input_hash", "units", "version")


def meta_json(se: Superelement, checksum: str | None = None) -> str:
    """One-line JSON of :data:`META_FIELDS` (floats written with full precision), and
    the content ``checksum`` last when given."""
    d = to_arrays(se)
    out = {}
    for k in META_FIELDS:
        v = d[k]
        out[k] = v.tolist() if isinstance(v, np.ndarray) else v
    if checksum is not None:
        out[CHECKSUM_KEY] = checksum
    return json.dumps(out, separators=(",", ":"))


def meta_from_json(text: str) -> dict:
    """The metadata dict of a superelement file from its JSON text (lists back to arrays)."""
    d = json.loads(text)
    for k in ("interface_positions", "interface_frames", "node_positions", "freq_hz",
              "center_of_mass", "inertia"):
        d[k] = np.asarray(d[k], dtype=np.float64).reshape(
            {"interface_positions": (-1, 3), "interface_frames": (-1, 3, 3),
             "node_positions": (-1, 3)}.get(k, np.shape(d[k])))
    d["node_interface"] = np.asarray(d["node_interface"], dtype=np.int64)
    return d
