"""Tiny links for the reduction tests: steel bars with interface regions at both ends."""

from __future__ import annotations

import pytest
from reduction_helpers import STEEL, end_regions

from flexarm.fe import TetMesh, assemble


@pytest.fixture(scope="session")
def bar():
    """Tet4 bar 0.4 x 0.04 x 0.04 m (8 x 2 x 2 cells), regions at both ends, K, M."""
    mesh = TetMesh.box((0.4, 0.04, 0.04), (8, 2, 2))
    return mesh, end_regions(0.4, 0.04), assemble(mesh, STEEL)


@pytest.fixture(scope="session")
def tiny_bar():
    """Tet4 bar 0.2 x 0.05 x 0.05 m (4 x 1 x 1 cells): small enough for all modes."""
    mesh = TetMesh.box((0.2, 0.05, 0.05), (4, 1, 1))
    return mesh, end_regions(0.2, 0.05), assemble(mesh, STEEL)


@pytest.fixture(scope="session")
def bar10():
    """Tet10 bar 0.3 x 0.04 x 0.04 m (6 x 1 x 1 cells)."""
    mesh = TetMesh.box((0.3, 0.04, 0.04), (6, 1, 1), order=2)
    return mesh, end_regions(0.3, 0.04), assemble(mesh, STEEL)


@pytest.fixture(autouse=True, scope="package")
def _small_matrix_solver():
    """SuperLU for these tiny matrices: creating a PARDISO handle searches the disk for
    MKL (about 1 s per factorisation), which would dominate the test time.  Package
    scope: the default is restored before any test outside ``tests/reduction`` runs."""
    from flexarm.fe.solvers import set_default_backend

    set_default_backend("splu")
    yield
    set_default_backend(None)
