"""Craig-Bampton reduction of one link across MPI ranks, on PETSc/MUMPS and SLEPc.

Run under ``mpiexec -n N``; every rank calls :func:`reduce_coupled_petsc` with the same
arguments.  Each rank

1. selects the interfaces and builds the coupling ``T`` (cheap, replicated);
2. assembles its element slice with the vectorised kernels and couples it
   (``T_s^T K_s T_s`` over the DOFs the slice touches, scipy);
3. sends each coupled entry to the rank owning its row: ``K_ii``, ``M_ii`` become
   distributed PETSc matrices, the thin ``K_ib``, ``M_ib`` blocks stay as owned dense
   rows, and the tiny ``K_bb``, ``M_bb`` are summed over ranks.

Then ``K_ii`` is factorised once by MUMPS (Cholesky).  That factor gives the constraint
modes (one multi-right-hand-side solve) and serves SLEPc's Krylov-Schur shift-invert
eigen-solve at ``sigma = 0`` (the same KSP is handed to the spectral transform, so
nothing is factorised twice).  The projection ``T^T K T`` is formed from owned rows
and summed over ranks; only the reduced matrices and the basis rows (the superelement's
recovery data) are gathered on rank 0.  The fixed-interface modes are mass-normalised
and signed exactly as :func:`flexarm.fe.eigen.modes` does, so the superelement equals
the one of the default path to round-off.
"""

from __future__ import annotations

import logging
import time

import numpy as np

from ..fe.errors import ConvergenceError, FlexarmError
from ..fe.material import Material
from ..fe.mesh import TetMesh
from ..fe.petsc_assembly import (
    aij_matrix,
    dense_matrix,
    element_owners,
    local_matrices,
    owned_rows,
    ownership_bounds,
    petsc,
    world,
)
from .couplings import Coupling, couple
from .craig_bampton import craig_bampton_basis
from .guyan import Reduction
from .interfaces import interfaces
from .projection import symmetric

__all__ = ["reduce_coupled_petsc", "EPS_TOL"]

log = logging.getLogger(__name__)

#: SLEPc's relative residual tolerance for the fixed-interface modes.  Eigenvalues are
#: then exact to ~tol^2 and the vectors to ~tol / gap: far inside the 1e-10 and 1e-9
#: that the superelement is compared with, at one or two more restarts than 1e-8.
EPS_TOL = 1e-13


def _slice(mesh: TetMesh, material: Material, c: Coupling, comm):
    """This rank's element slice: its K, M and the rows ``T_s`` of the coupling."""
    mine = np.flatnonzero(element_owners(mesh, comm.Get_size()) == comm.Get_rank())
    part = local_matrices(mesh, material, mine)
    return part, c.T[part.dofs]


def _coupled_blocks(A_s, T_s, n_i: int, bounds, comm):
    """Coupled ``T_s^T A_s T_s`` summed over ranks, in blocks: distributed ``A_ii``
    (PETSc), owned dense rows of ``A_ib``, and ``A_bb`` (on every rank)."""
    from mpi4py import MPI

    A = (T_s.T @ A_s @ T_s).tocsr()
    A_ii = owned_rows(A[:n_i, :n_i], bounds, comm)
    A_ib = owned_rows(A[:n_i, n_i:], bounds, comm).toarray()
    A_bb = A[n_i:, n_i:].toarray()
    del A
    total = np.zeros_like(A_bb)
    comm.Allreduce(A_bb, total, op=MPI.SUM)
    return aij_matrix(A_ii, bounds, bounds, comm), A_ib, total


def _factor(K_ii):
    """A KSP that applies ``K_ii^-1`` by a MUMPS Cholesky factor (factorised now)."""
    PETSc = petsc()
    opts = PETSc.Options()
    if not opts.hasName("mat_mumps_icntl_7"):
        # METIS ordering: on a 30k-DOF Tet10 link 2.4 s instead of 3.9 s with MUMPS'
        # automatic choice (the user's PETSC_OPTIONS win)
        opts["mat_mumps_icntl_7"] = 5
    K_ii.setOption(PETSc.Mat.Option.SYMMETRIC, True)
    K_ii.setOption(PETSc.Mat.Option.SPD, True)
    ksp = PETSc.KSP().create(comm=K_ii.getComm())
    ksp.setOperators(K_ii)
    ksp.setType("preonly")
    pc = ksp.getPC()
    pc.setType("cholesky")
    pc.setFactorSolverType("mumps")
    ksp.setFromOptions()
    ksp.setUp()
    return ksp


def _constraint_modes(ksp, K_ib: np.ndarray, bounds, comm) -> np.ndarray:
    """Owned rows (m, n_b) of ``-K_ii^-1 K_ib``: one multi-RHS MUMPS solve."""
    B = dense_matrix(-K_ib, bounds, comm)
    X = B.duplicate()
    ksp.getPC().getFactorMatrix().matSolve(B, X)
    return np.array(X.getDenseArray(), copy=True)


def _fixed_modes(ksp, K_ii, M_ii, n: int, bounds, comm):
    """``n`` lowest (omega2, owned vector rows) of ``K_ii x = omega^2 M_ii x`` (SLEPc)."""
    from slepc4py import SLEPc

    eps = SLEPc.EPS().create(comm=K_ii.getComm())
    eps.setOperators(K_ii, M_ii)
    eps.setProblemType(SLEPc.EPS.ProblemType.GHEP)
    eps.setType(SLEPc.EPS.Type.KRYLOVSCHUR)
    eps.setDimensions(nev=n)
    eps.setTarget(0.0)
    eps.setWhichEigenpairs(SLEPc.EPS.Which.TARGET_MAGNITUDE)
    eps.setTolerances(tol=EPS_TOL, max_it=1000)
    st = eps.getST()
    st.setType(SLEPc.ST.Type.SINVERT)
    st.setShift(0.0)
    st.setKSP(ksp)  # K - 0 M = K_ii: the factor already made serves every solve
    eps.setFromOptions()
    eps.solve()
    found = eps.getConverged()
    if found < n:
        raise ConvergenceError(f"SLEPc converged {found} of {n} fixed-interface modes")
    w = np.array([eps.getEigenvalue(i).real for i in range(n)])
    x = K_ii.createVecRight()
    V = np.zeros((int(bounds[comm.Get_rank() + 1] - bounds[comm.Get_rank()]), n))
    for i in range(n):
        eps.getEigenvector(i, x)
        V[:, i] = x.getArray()
    log.info("SLEPc: %d modes, %d iterations, %d converged", n, eps.getIterationNumber(), found)
    return w, V


def _normalised(w, V, M_ii, bounds, comm):
    """Sorted, mass-normalised, signed as :func:`flexarm.fe.eigen.modes` signs them."""
    order = np.argsort(w, kind="stable")
    w, V = w[order], V[:, order]
    MV = _mat_dense(M_ii, V, bounds, comm)
    from mpi4py import MPI

    norms = np.zeros(V.shape[1])
    comm.Allreduce(np.einsum("ik,ik->k", V, MV), norms, op=MPI.SUM)
    V = V / np.sqrt(norms)
    rank = comm.Get_rank()
    probe = np.random.default_rng(12345).standard_normal(int(bounds[-1]))
    proj = np.zeros(V.shape[1])
    comm.Allreduce(probe[bounds[rank]:bounds[rank + 1]] @ V, proj, op=MPI.SUM)
    signs = np.sign(proj)
    return w, V * np.where(signs == 0, 1.0, signs)


def _mat_dense(A, V: np.ndarray, bounds, comm) -> np.ndarray:
    """Owned rows of ``A @ V`` for a distributed sparse ``A`` and owned rows ``V``."""
    D = dense_matrix(V, bounds, comm)
    return np.array(A.matMult(D).getDenseArray(), copy=True)


def _projected(A_ii, A_ib, A_bb, V, bounds, comm) -> np.ndarray:
    """``T^T A T`` with ``T = [[V], [I, 0]]`` (boundary last), summed over ranks."""
    from mpi4py import MPI

    n_b = A_ib.shape[1]
    AV = _mat_dense(A_ii, V, bounds, comm)
    part = np.zeros((V.shape[1], V.shape[1] + n_b))
    part[:, : V.shape[1]] = V.T @ AV
    part[:, V.shape[1]:] = V.T @ A_ib
    total = np.zeros_like(part)
    comm.Allreduce(part, total, op=MPI.SUM)
    A_r = total[:, : V.shape[1]]
    A_r[:, :n_b] += total[:, V.shape[1]:]
    A_r[:n_b, :] += total[:, V.shape[1]:].T
    A_r[:n_b, :n_b] += A_bb
    return symmetric(A_r)


def _gather_rows(V: np.ndarray, comm):
    """All ranks' rows of ``V`` stacked in rank order on rank 0 (None elsewhere)."""
    counts = np.array(comm.allgather(V.size), dtype=np.int64)
    buf = np.zeros((int(counts.sum()) // max(V.shape[1], 1), V.shape[1])) \
        if comm.Get_rank() == 0 else None
    comm.Gatherv(np.ascontiguousarray(V), [buf, counts] if buf is not None else None, root=0)
    return buf


def reduce_coupled_petsc(mesh: TetMesh, material: Material, regions, coupling: str = "rbe2",
                         n_modes: int = 20, n_masters: int | None = None,
                         diagonal: bool = False, surface_only: bool = True):
    """Couple and reduce a link on all MPI ranks (call it on every rank).

    Parameters are those of :func:`flexarm.reduction.reduce.reduce_with_stats`;
    ``n_modes = 0`` gives Guyan.

    Returns
    -------
    ifaces : tuple of Interface
    coupling : Coupling
    reduction : Reduction or None
        On rank 0: reduced K [N/m ...], M [kg ...], the basis ``T`` (n_c, n_b + n_modes)
        over the coupled DOFs, the fixed-interface ``omega2`` [rad^2/s^2] and wall times
        [s]; ``None`` on the other ranks.
    seconds_assemble : float
        Wall time of the distributed assembly and coupling [s].
    """
    comm = world()
    t0 = time.perf_counter()
    ifaces = interfaces(mesh, regions, surface_only)
    c = couple(mesh, ifaces, coupling, n_masters)
    n_i, n_b = c.n_interior, c.n_boundary
    if n_modes > n_i:
        raise ValueError(f"asked for {n_modes} fixed-interface modes but there are only "
                         f"{n_i} interior DOFs")
    if n_i < comm.Get_size():
        raise FlexarmError(f"{n_i} interior DOFs cannot be shared by {comm.Get_size()} ranks")
    bounds = ownership_bounds(n_i, comm.Get_size())
    part, T_s = _slice(mesh, material, c, comm)
    K_ii, K_ib, K_bb = _coupled_blocks(part.K, T_s, n_i, bounds, comm)
    M_ii, M_ib, M_bb = _coupled_blocks(part.M, T_s, n_i, bounds, comm)
    del part, T_s
    t1 = time.perf_counter()
    ksp = _factor(K_ii)
    t2 = time.perf_counter()
    Psi = _constraint_modes(ksp, K_ib, bounds, comm)
    t3 = time.perf_counter()
    w = np.zeros(0)
    Phi = np.zeros((Psi.shape[0], 0))
    if n_modes > 0:
        w, Phi = _fixed_modes(ksp, K_ii, M_ii, n_modes, bounds, comm)
        w, Phi = _normalised(w, Phi, M_ii, bounds, comm)
    t4 = time.perf_counter()
    V = np.hstack([Psi, Phi])
    K_r = _projected(K_ii, K_ib, K_bb, V, bounds, comm)
    M_r = _projected(M_ii, M_ib, M_bb, V, bounds, comm)
    if diagonal and n_modes > 0:
        K_r[n_b:, n_b:] = np.diag(w)
        M_r[n_b:, n_b:] = np.eye(n_modes)
        K_r[:n_b, n_b:] = 0.0
        K_r[n_b:, :n_b] = 0.0
    rows = _gather_rows(V, comm)
    t5 = time.perf_counter()
    log.info("PETSc Craig-Bampton on %d ranks: %d -> %d + %d DOF in %.2f s",
             comm.Get_size(), c.n_coupled, n_b, n_modes, t5 - t0)
    if comm.Get_rank() != 0:
        return ifaces, c, None, t1 - t0
    T = craig_bampton_basis(rows[:, :n_b], rows[:, n_b:])
    seconds = {"factorise": t2 - t1, "constraint_modes": t3 - t2}
    if n_modes > 0:
        seconds["eigen"] = t4 - t3
    seconds["projection"] = t5 - t4
    return ifaces, c, Reduction(K_r, M_r, T, n_b, w, seconds), t1 - t0
