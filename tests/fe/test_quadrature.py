"""Tet quadrature: products of barycentric coordinates (all four, so the rule is checked for
the tet's vertex symmetry) against alpha! / (|alpha| + 3)!, point counts, caching."""

from __future__ import annotations

from itertools import product
from math import ceil, factorial, prod

import numpy as np
import pytest

from flexarm.fe import tet_quadrature


def _barycentric(pts):
    return np.column_stack([1.0 - pts.sum(axis=1), pts])


@pytest.mark.parametrize("degree", range(1, 8))
def test_barycentric_products_exact_to_the_degree(degree):
    """int L0^a L1^b L2^c L3^d over the reference tet = a! b! c! d! / (a + b + c + d + 3)!."""
    pts, w = tet_quadrature(degree)
    L = _barycentric(pts)
    for alpha in product(range(degree + 1), repeat=4):
        if sum(alpha) > degree:
            continue
        exact = prod(factorial(k) for k in alpha) / factorial(sum(alpha) + 3)
        got = w @ np.prod(L ** np.array(alpha), axis=1)
        assert got == pytest.approx(exact, rel=1e-13, abs=0), alpha


@pytest.mark.parametrize("degree, n_points", [(-1, 1), (0, 1), (1, 1), (2, 4), (3, 8), (4, 27),
                                              (5, 27), (6, 64), (9, 125)])
def test_point_counts_and_weights(degree, n_points):
    pts, w = tet_quadrature(degree)
    assert pts.shape == (n_points, 3) and w.shape == (n_points,)
    assert w.sum() == pytest.approx(1 / 6, rel=1e-14)
    assert np.all(w > 0) and np.all(pts > 0) and np.all(pts.sum(axis=1) < 1)
    if degree >= 3:
        assert n_points == ceil((degree + 1) / 2) ** 3


def test_low_rules_are_symmetric():
    """The 1- and 4-point rules are invariant under permuting the tet's four vertices."""
    pts, _ = tet_quadrature(1)
    np.testing.assert_array_equal(pts, [[0.25] * 3])
    L = np.sort(_barycentric(tet_quadrature(2)[0]), axis=1)
    np.testing.assert_allclose(L, np.tile(L[0], (4, 1)), rtol=1e-15)
    # a = (5 + 3 sqrt 5) / 20, b = (5 - sqrt 5) / 20
    np.testing.assert_allclose(L[0], [(5 - 5**0.5) / 20] * 3 + [(5 + 3 * 5**0.5) / 20],
                               rtol=1e-15)


def test_rules_are_cached_and_read_only():
    pts, w = tet_quadrature(5)
    again = tet_quadrature(5)
    assert again[0] is pts and again[1] is w
    with pytest.raises(ValueError, match="read-only"):
        w[0] = 1.0
    with pytest.raises(ValueError, match="read-only"):
        pts[0, 0] = 1.0
