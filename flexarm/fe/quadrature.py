"""Quadrature rules on the reference tetrahedron {x, y, z >= 0, x + y + z <= 1}."""

from __future__ import annotations

from functools import cache

import numpy as np
from scipy.special import roots_jacobi, roots_legendre

__all__ = ["tet_quadrature"]


@cache
def tet_quadrature(degree: int) -> tuple[np.ndarray, np.ndarray]:
    """Points (q, 3) and weights (q,) exact for polynomials up to ``degree``.

    Degrees 1 and 2 use the classical 1- and 4-point rules.  Higher degrees use the
    conical (Stroud) product of Gauss-Legendre and Gauss-Jacobi rules in collapsed
    coordinates, which has positive weights only; ``n = ceil((degree + 1) / 2)``
    points per direction.

    The weights sum to the reference volume 1/6.

    Examples
    --------
    >>> pts, w = tet_quadrature(4)
    >>> pts.shape, round(float(w.sum() * 6), 14)
    ((27, 3), 1.0)
    >>> # int x^2 y z over the reference tet = 2! 1! 1! / 7! = 1/2520
    >>> round(float(w @ (pts[:, 0] ** 2 * pts[:, 1] * pts[:, 2]) * 2520), 12)
    1.0
    """
    if degree <= 1:
        pts = np.full((1, 3), 0.25)
        w = np.array([1.0 / 6.0])
    elif degree == 2:
        a, b = 0.5854101966249685, 0.1381966011250105
        pts = np.array([[b, b, b], [a, b, b], [b, a, b], [b, b, a]])
        w = np.full(4, 1.0 / 24.0)
    else:
        n = int(np.ceil((degree + 1) / 2))
        xa, wa = roots_legendre(n)
        xb, wb = roots_jacobi(n, 1.0, 0.0)
        xc, wc = roots_jacobi(n, 2.0, 0.0)
        a, b, c = (xa + 1) / 2, (xb + 1) / 2, (xc + 1) / 2
        wa, wb, wc = wa / 2, wb / 4, wc / 8
        A, B, C = np.meshgrid(a, b, c, indexing="ij")
        W = np.einsum("i,j,k->ijk", wa, wb, wc)
        z = C
        y = B * (1 - C)
        x = A * (1 - B) * (1 - C)
        pts = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
        w = W.ravel()
    pts.setflags(write=False)
    w.setflags(write=False)
    return pts, w
