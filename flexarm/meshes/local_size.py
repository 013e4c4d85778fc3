"""Where a tet mesh must be finer than its edge: cylinders with a smaller local edge.

A bearing seat on a coarse mesh can be smaller than a few elements: the coupling then
holds too few nodes, or none.  A :class:`LocalSize` asks the mesher for an edge of at
most ``size`` inside a cylinder (a seat region, in the part's frame), growing by
:data:`GRADING` metres per metre of distance outside it, so that the elements coarsen
back to the global edge over a few layers instead of in one jump.

Only Gmsh takes local sizes (a size callback on every meshing pass,
:mod:`.gmsh_mesher`); the fTetWild fallback meshes at its global edge.  The sizes enter
the cache key only when there are any, so a part without them keeps its cached mesh.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

__all__ = ["GRADING", "LocalSize", "local_size_at", "local_sizes_key", "size_callback"]

#: Growth of the local edge with the distance outside its cylinder [m per m].
GRADING = 0.5
#: Part of the cache key: a new meshing recipe with local sizes never reuses an old mesh.
_RECIPE = 2


@dataclass(frozen=True)
class LocalSize:
    """An edge of at most ``size`` [m] inside the cylinder about the axis through
    ``center`` along the unit ``axis`` (part frame [m]), of radius ``radius`` [m] and
    axial half-length ``half_width`` [m].

    Examples
    --------
    >>> c = LocalSize((0, 0, 0), (0, 0, 1), 0.1, 0.01, 0.02)
    >>> c.distance(0.05, 0, 0), round(c.distance(0.2, 0, 0), 12), c.distance(0, 0, 0.04)
    (0.0, 0.1, 0.03)
    """

    center: tuple
    axis: tuple
    radius: float
    half_width: float
    size: float

    def __post_init__(self) -> None:
        if not (self.size > 0 and self.radius >= 0 and self.half_width >= 0):
            raise ValueError(f"a local size needs size > 0, radius >= 0 and half_width >= 0 "
                             f"[m], got {self.size}, {self.radius}, {self.half_width}")
        n = math.sqrt(sum(float(a) ** 2 for a in self.axis))
        if not abs(n - 1.0) < 1e-9:
            raise ValueError(f"a local size's axis must be a unit (3,) vector, got {self.axis}")

    def distance(self, x: float, y: float, z: float) -> float:
        """Distance [m] of the point (x, y, z) from the cylinder (0 inside it)."""
        cx, cy, cz = self.center
        ax, ay, az = self.axis
        dx, dy, dz = x - cx, y - cy, z - cz
        t = dx * ax + dy * ay + dz * az
        r = math.sqrt(max(dx * dx + dy * dy + dz * dz - t * t, 0.0))
        out_r = max(r - self.radius, 0.0)
        out_t = max(abs(t) - self.half_width, 0.0)
        return math.hypot(out_r, out_t)

    def key(self) -> tuple:
        """The cylinder and size as plain floats (a cache-key part)."""
        return (tuple(map(float, self.center)), tuple(map(float, self.axis)),
                float(self.radius), float(self.half_width), float(self.size))


def local_size_at(local_sizes: Sequence[LocalSize], x: float, y: float, z: float,
                  size: float) -> float:
    """The edge [m] to ask for at (x, y, z) [m]: ``size`` unless a local size is finer
    there (its ``size`` plus :data:`GRADING` times the distance from its cylinder).

    Examples
    --------
    >>> c = LocalSize((0, 0, 0), (0, 0, 1), 0.1, 0.01, 0.02)
    >>> local_size_at([c], 0, 0, 0, 0.08), round(local_size_at([c], 0.14, 0, 0, 0.08), 12)
    (0.02, 0.04)
    >>> local_size_at([c], 1.0, 0, 0, 0.08)
    0.08
    """
    best = float(size)
    for c in local_sizes:
        best = min(best, c.size + GRADING * c.distance(x, y, z))
    return best


def size_callback(local_sizes: Sequence[LocalSize],
                  scale: float = 1.0) -> Callable[[int, int, float, float, float, float], float]:
    """Gmsh's ``setSizeCallback`` function: the size Gmsh would use, or the local one
    (times ``scale``: a pre-mesh at a fraction of the edge) where that is finer.

    Examples
    --------
    >>> cb = size_callback([LocalSize((0, 0, 0), (0, 0, 1), 0.1, 0.01, 0.02)], 0.5)
    >>> cb(2, 1, 0.0, 0.0, 0.0, 0.04), cb(2, 1, 1.0, 0.0, 0.0, 0.04)
    (0.01, 0.04)
    """
    sizes = tuple(local_sizes)

    def callback(dim: int, tag: int, x: float, y: float, z: float, lc: float) -> float:
        return min(lc, scale * local_size_at(sizes, x, y, z, math.inf))

    return callback


def local_sizes_key(local_sizes: Sequence[LocalSize]) -> tuple:
    """Cache-key part of ``local_sizes``: empty when there are none (a part without them
    keeps the key it had before local sizes existed).

    >>> local_sizes_key(())
    ()
    >>> local_sizes_key([LocalSize((0, 0, 0), (0, 0, 1), 0.1, 0.01, 0.02)])[0]
    'local sizes'
    """
    if not local_sizes:
        return ()
    return ("local sizes", _RECIPE, GRADING, tuple(c.key() for c in local_sizes))
