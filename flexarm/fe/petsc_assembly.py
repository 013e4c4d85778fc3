"""Distributed assembly under MPI: each rank assembles its element slice into PETSc.

Every rank holds the whole mesh (a few tens of MB even for a million-DOF link) and
assembles only its slice of the elements with the same vectorised kernels and sparsity
code as :func:`flexarm.fe.assembly.assemble`, into a CSR matrix over the DOFs that
slice touches.  The caller maps those entries to the numbering it wants (the coupled
DOFs of a reduction, say); :func:`owned_rows` then sends every entry to the rank that
owns its row (one ``Alltoallv``), where they are summed in a fixed order, and
:func:`aij_matrix` wraps the owned rows as a PETSc ``MPIAIJ`` matrix with exact
preallocation.  Rows are owned in contiguous ranges, as PETSc requires
(:func:`ownership_bounds`).

petsc4py and mpi4py are imported on first use only (:func:`petsc`); without them the
rest of flexarm works as before.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .assembly import assemble
from .errors import MissingDependencyError
from .material import Material
from .mesh import TetMesh

__all__ = [
    "petsc",
    "world",
    "is_distributed",
    "ownership_bounds",
    "element_owners",
    "LocalMatrices",
    "local_matrices",
    "owned_rows",
    "aij_matrix",
    "dense_matrix",
]

log = logging.getLogger(__name__)

_HINT = ("the PETSc backend (on Debian/Ubuntu `bash install.sh --mpi` builds "
         ".venv/mpi/bin/flexarm with Debian's PETSc; on a cluster, against its PETSc)")


def petsc():
    """The initialised ``petsc4py.PETSc`` module (imported on first use).

    PETSc options come from the ``PETSC_OPTIONS`` environment variable, e.g.
    ``PETSC_OPTIONS="-mat_mumps_icntl_14 50"`` for more MUMPS workspace.
    """
    try:
        import petsc4py
    except ImportError:
        raise MissingDependencyError("petsc4py", _HINT) from None
    petsc4py.init([])
    from petsc4py import PETSc

    return PETSc


def world():
    """The MPI world communicator as an ``mpi4py`` communicator."""
    return petsc().COMM_WORLD.tompi4py()


def is_distributed() -> bool:
    """True when this process is one of several MPI ranks (and petsc4py is importable).

    Looks at the launcher's environment first, so a plain run never imports MPI.
    """
    import os

    launched = any(k in os.environ for k in ("OMPI_COMM_WORLD_SIZE", "PMI_SIZE",
                                               "PMIX_RANK", "MPI_LOCALNRANKS"))
    if not launched:
        return False
    try:
        return world().Get_size() > 1
    except MissingDependencyError:
        return False


def ownership_bounds(n: int, size: int) -> np.ndarray:
    """(size + 1,) int row bounds: rank ``r`` owns rows ``bounds[r]:bounds[r+1]``.

    PETSc's default split (``PETSC_DECIDE``): the first ``n % size`` ranks get one row more.

    >>> ownership_bounds(10, 3).tolist()
    [0, 4, 7, 10]
    """
    counts = np.full(size, n // size, dtype=np.int64)
    counts[: n % size] += 1
    return np.concatenate([[0], np.cumsum(counts)])


def element_owners(mesh: TetMesh, size: int) -> np.ndarray:
    """(n_tets,) int rank of each element: equal shares, in the order of their node 0.

    Elements sorted by their first (corner) node are cut into ``size`` contiguous runs
    of equal length (:func:`ownership_bounds`), so every rank assembles the same number
    of elements and neighbouring elements mostly share a rank.  (Splitting by node
    ranges instead would starve ranks on Tet10 meshes, which number the mid-edge nodes
    after all corners.)

    >>> m = TetMesh.box(divisions=(2, 1, 1), order=2)
    >>> np.bincount(element_owners(m, 4)).tolist()
    [3, 3, 3, 3]
    """
    n = mesh.n_tets
    order = np.argsort(mesh.tets[:, 0], kind="stable")
    owners = np.zeros(n, dtype=np.int64)
    owners[order] = np.searchsorted(ownership_bounds(n, size)[1:-1], np.arange(n),
                                    side="right")
    return owners


@dataclass(frozen=True, eq=False)
class LocalMatrices:
    """Stiffness and mass of one element slice over the FE DOFs it touches.

    Attributes
    ----------
    dofs : (k,) int
        Global FE DOF (``3*node + component``) of each local row/column.
    K, M : (k, k) sparse CSR
        Slice stiffness [N/m] and consistent mass [kg].
    """

    dofs: np.ndarray
    K: sp.csr_matrix
    M: sp.csr_matrix


def local_matrices(mesh: TetMesh, material: Material, elements: np.ndarray) -> LocalMatrices:
    """K and M of the elements ``elements`` (int indices), over the DOFs they touch.

    The slice is a mesh of its own (its nodes renumbered compactly), assembled by
    :func:`flexarm.fe.assembly.assemble`: the same kernels, the same sums.

    >>> from flexarm.fe.material import MATERIALS
    >>> m = TetMesh.box(divisions=(2, 1, 1))
    >>> part = local_matrices(m, MATERIALS["steel"], np.arange(6))  # the first cube
    >>> part.dofs.size, part.K.shape
    (24, (24, 24))
    """
    tets = mesh.tets[np.asarray(elements, dtype=np.int64)]
    nodes, local = np.unique(tets, return_inverse=True)
    sub = TetMesh(mesh.points[nodes], local.reshape(tets.shape))
    K, M = assemble(sub, material) if len(tets) else (sp.csr_matrix((0, 0)),) * 2
    dofs = (3 * nodes[:, None] + np.arange(3)).reshape(-1)
    return LocalMatrices(dofs, sp.csr_matrix(K), sp.csr_matrix(M))


def owned_rows(A: sp.csr_matrix, bounds: np.ndarray, comm) -> sp.csr_matrix:
    """The rows this rank owns of the sum over all ranks of ``A``, as local CSR.

    Parameters
    ----------
    A : (n_rows, n_cols) sparse CSR
        This rank's contributions, global numbering.
    bounds : (size + 1,) int
        Row ownership (:func:`ownership_bounds`).
    comm : mpi4py communicator

    Returns
    -------
    (bounds[r+1] - bounds[r], n_cols) CSR with sorted indices.  CSR rows bound for one
    rank are contiguous, so they are sent straight from ``A``'s arrays (one
    ``Alltoallv`` each for row lengths, columns and values, no copy); the pieces are
    summed in rank order, so the result does not depend on timing.
    """
    A = sp.csr_matrix(A)
    A.sum_duplicates()
    size, rank = comm.Get_size(), comm.Get_rank()
    if size == 1:
        A.sort_indices()
        return A
    row_counts = np.diff(bounds).astype(np.int64)
    m = int(row_counts[rank])
    counts = np.diff(A.indptr[bounds]).astype(np.int64)
    recv = np.zeros(size, dtype=np.int64)
    comm.Alltoall(counts, recv)
    lengths = np.zeros(size * m, dtype=np.int64)
    comm.Alltoallv([np.diff(A.indptr).astype(np.int64), row_counts],
                   [lengths, np.full(size, m, dtype=np.int64)])
    got = []
    for send in (A.indices, A.data):
        buf = np.zeros(int(recv.sum()), dtype=send.dtype)
        comm.Alltoallv([np.ascontiguousarray(send), counts], [buf, recv])
        got.append(buf)
    out = sp.csr_matrix((m, A.shape[1]))
    at = np.concatenate([[0], np.cumsum(recv)])
    for src in range(size):  # one piece per rank, added in rank order
        ptr = np.concatenate([[0], np.cumsum(lengths[src * m:(src + 1) * m])])
        piece = sp.csr_matrix((got[1][at[src]:at[src + 1]], got[0][at[src]:at[src + 1]], ptr),
                              shape=(m, A.shape[1]))
        out = out + piece
    out.sort_indices()
    return out


def aij_matrix(local: sp.csr_matrix, bounds: np.ndarray, col_bounds: np.ndarray, comm):
    """A PETSc ``MPIAIJ`` matrix from this rank's owned rows (exact preallocation).

    ``bounds``/``col_bounds`` give the row and column ownership; ``local`` holds the
    owned rows with global column numbers.
    """
    PETSc = petsc()
    rank = comm.Get_rank()
    m = int(bounds[rank + 1] - bounds[rank])
    n = int(col_bounds[rank + 1] - col_bounds[rank])
    csr = (local.indptr.astype(PETSc.IntType, copy=False),
           local.indices.astype(PETSc.IntType, copy=False),
           local.data.astype(PETSc.ScalarType, copy=False))
    A = PETSc.Mat().createAIJ(((m, int(bounds[-1])), (n, int(col_bounds[-1]))), csr=csr,
                              comm=PETSc.COMM_WORLD)
    A.assemble()
    return A


def dense_matrix(local: np.ndarray, bounds: np.ndarray, comm):
    """A PETSc ``MPIDense`` matrix (n, k) holding this rank's rows ``local`` (m, k).

    The values are copied in (PETSc keeps its own column-major storage).
    """
    PETSc = petsc()
    rank = comm.Get_rank()
    m, k = local.shape
    assert m == bounds[rank + 1] - bounds[rank]
    D = PETSc.Mat().createDense(((m, int(bounds[-1])), (None, k)), comm=PETSc.COMM_WORLD)
    D.setUp()
    D.getDenseArray()[:] = local
    D.assemble()
    return D
