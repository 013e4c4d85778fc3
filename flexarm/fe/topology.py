"""Local node numbering of the tetrahedron (VTK order), shared by meshes and elements."""

from __future__ import annotations

import numpy as np

__all__ = ["TET10_EDGES", "TET_FACES"]

#: Local corner pairs of the six Tet10 mid-edge nodes 4..9 (VTK order).
TET10_EDGES = np.array([[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]], dtype=np.int64)
#: Local corner triples of the four faces, each oriented outward for a positive tet.
TET_FACES = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]], dtype=np.int64)
