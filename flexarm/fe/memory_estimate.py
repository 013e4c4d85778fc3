"""How much memory a reduction will take, known before any matrix is assembled.

The dominant term is the sparse factor of the interior stiffness.  Its fill is read from
the analysis phase of the ordering that the factorisation itself uses (PARDISO's METIS
nested dissection and symbolic factorisation, :func:`flexarm.fe.pardiso.factor_size`),
run on the *node* graph of the mesh: a third of the size and a ninth of the entries of
the DOF matrix, so it takes a fraction of a second to a few seconds, and the DOF-level
factor has ``9 L_nodes - 3 n_nodes`` entries (measured: 0.97-0.99 of the DOF-level
analysis on Tet10 links of 29k and 140k DOF).  The rest (matrices and their coupled
copies, the dense basis, the recovery matrix, the Krylov basis) follows from counts.

:func:`plan_memory` turns the estimate into a path: the in-core default when it fits in
the memory available, in core with a single-precision factor (refined to double
accuracy, :mod:`flexarm.fe.refinement`) when only that fits, PETSc across MPI ranks when
the process runs under ``mpiexec`` and each host's share fits, else
:class:`InsufficientMemoryError` with the figures and the cluster command.  Small links
skip the analysis: a generous closed-form bound already fits.
"""

from __future__ import annotations

import logging
import os
from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp

from .errors import FlexarmError
from .mesh import TetMesh
from .quantities import Quantity, env_number

__all__ = [
    "InsufficientMemoryError",
    "MemoryEstimate",
    "MemoryPlan",
    "available_memory",
    "estimate_memory",
    "plan_memory",
]

log = logging.getLogger(__name__)

GB = 1024.0**3
#: ``FLEXARM_MEMORY_GB``: a bare number is GB (1024**3 bytes, as :data:`GB`); the value
#: returned is bytes.
_MEMORY_CAP = Quantity("memory", "GB", 0, 1e6, open_low=True, result="B")
#: Bytes per factor entry: the float64 value plus PARDISO's supernodal indices, fitted
#: (with the terms below) to the whole measured peak of CB reductions of Tet10 bars since
#: the full matrices are freed before the factor is made: estimate / measured 1.38 at 29k
#: DOF, 1.26 at 200k (2.19 GB), 1.23 at 1.0M (16.3 GB).  (PARDISO's own peak over 8 x
#: entries: 1.36 at 140k DOF, 1.77 at 29k DOF; the other terms are generous on large links.)
FACTOR_BYTES_PER_ENTRY = 9.0
#: The same for a single-precision factor (the float32 value plus PARDISO's indices):
#: estimate / measured 1.48 at 29k DOF, 1.16 at 1.0M (11.4 GB), 1.27 at 1.52M (17.2 GB).
FACTOR_BYTES_PER_ENTRY_SINGLE = 4.5
#: MUMPS's factor against PARDISO's for the same fill (its ICNTL(14) workspace and the
#: distributed copy of the matrix it receives), fitted to whole measured PETSc peaks of CB
#: reductions of Tet10 bars on one rank: estimate / measured 1.34 at 200k DOF (2.33 GB),
#: 1.32 at 500k (7.38 GB), 1.22 at 1.0M (19.1 GB); per rank on two ranks 1.2-1.27.
MUMPS_OVERHEAD = 1.25
#: Each of N ranks holds ``N ** -RANK_SHARE_EXPONENT`` of the one-rank factor and
#: matrices, not ``1/N``: the top of MUMPS's elimination tree and the gathered pieces do
#: not split evenly.  Fitted to the 2-rank run at 1.0M DOF that ran out of memory here
#: (one rank killed at 13.3 GB, where an even split predicts 12.0 GB; this gives 16.0 GB).
RANK_SHARE_EXPONENT = 0.57
#: Sparse matrices alive at once during a reduction, in units of one K (CSR, 12 bytes an
#: entry): K, M (a third of K's entries), the coupled copies, the interior blocks and
#: PARDISO's upper triangle.
SPARSE_COPIES = 4.0
#: Dense float64 columns of length n alive at once beyond the basis: Krylov basis and
#: block vectors of the eigen-solve.
KRYLOV_COLUMNS = 80
#: Fixed workspace of the libraries [bytes]: PARDISO alone reports 16 MB for a 3 x 3
#: matrix; thread pools and allocator slack add to it.
FIXED_BYTES = 100e6
#: Closed-form bound on the factor's entries, ``c n_dofs^(4/3)`` (3-D nested dissection):
#: c = 12-13 was measured on Tet10 bars; 60 leaves room for compact parts.
FILL_BOUND = 60.0
#: Below this share of the available memory the closed-form bound is trusted and the
#: analysis is skipped.
BOUND_SHARE = 0.25


def _gb(x: float) -> str:
    return f"{x / GB:.3g} GB"


class InsufficientMemoryError(FlexarmError):
    """The reduction would not fit in the memory of this machine (or of each host)."""


@dataclass(frozen=True)
class MemoryEstimate:
    """Memory a reduction needs [bytes], by part.

    Attributes
    ----------
    n_dofs : int
        FE DOFs (3 per node).
    factor_entries : int
        Entries of the factor of the stiffness (METIS fill).
    factor_bytes, sparse_bytes, dense_bytes : float
        The factor, the sparse matrices, the dense basis and vectors (with the
        libraries' fixed workspace) [bytes].
    method : str
        ``"analysis"`` (PARDISO's symbolic phase on the node graph) or ``"bound"``
        (closed-form upper bound, for small links or without PARDISO).
    precision : {"double", "single"}
        Precision of the factor counted.
    """

    n_dofs: int
    factor_entries: int
    factor_bytes: float
    sparse_bytes: float
    dense_bytes: float
    method: str
    precision: str = "double"

    @property
    def total_bytes(self) -> float:
        """In-core peak of the default path [bytes]."""
        return self.factor_bytes + self.sparse_bytes + self.dense_bytes

    def per_rank_bytes(self, ranks: int) -> float:
        """Peak of one of ``ranks`` PETSc ranks [bytes] (rank 0 also gathers the basis)."""
        share = float(ranks) ** -RANK_SHARE_EXPONENT
        shared = (MUMPS_OVERHEAD * self.factor_bytes + self.sparse_bytes
                  + self.dense_bytes / 2) * share
        return shared + self.dense_bytes / 2

    def in_precision(self, precision: str) -> MemoryEstimate:
        """The same estimate with the factor stored in ``precision``."""
        per_entry = (FACTOR_BYTES_PER_ENTRY_SINGLE if precision == "single"
                     else FACTOR_BYTES_PER_ENTRY)
        return replace(self, factor_bytes=per_entry * self.factor_entries, precision=precision)

    def text(self) -> str:
        """One line: total and factor [GB], how the fill was found."""
        how = "METIS analysis" if self.method == "analysis" else "closed-form bound"
        single = ("" if self.precision == "double" else
                  " with a single-precision factor")
        return (f"{self.n_dofs} DOF: about {_gb(self.total_bytes)} in core{single} (factor "
                f"{_gb(self.factor_bytes)}, {self.factor_entries:.3g} entries by {how})")


@dataclass(frozen=True)
class MemoryPlan:
    """The path a reduction takes, and why.

    Attributes
    ----------
    backend : str or None
        Solver backend to use (``None``: the in-core default; ``"petsc"``).
    path : {"in-core", "petsc"}
    estimate : MemoryEstimate
    available_bytes : float
        Memory available on this host [bytes].
    ranks : int
        MPI ranks sharing the work (1 in core).
    precision : {"double", "single"}
        Precision of the factor (``"single"`` when only that fits in core).
    """

    backend: str | None
    path: str
    estimate: MemoryEstimate
    available_bytes: float
    ranks: int = 1
    precision: str = "double"


def available_memory() -> float:
    """Memory this process may still use [bytes].

    The smaller of the kernel's ``MemAvailable`` and the cgroup limit less its usage;
    ``FLEXARM_MEMORY_GB`` overrides both (a cap for shared machines, or for tests).

    >>> available_memory() > 0
    True
    """
    cap = env_number("FLEXARM_MEMORY_GB", _MEMORY_CAP)
    if cap is not None:
        return cap
    found = []
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    found.append(float(line.split()[1]) * 1024)
    except OSError:
        pass
    try:
        with open("/sys/fs/cgroup/memory.max") as f:
            limit = f.read().strip()
        if limit != "max":
            with open("/sys/fs/cgroup/memory.current") as f:
                found.append(float(limit) - float(f.read()))
    except (OSError, ValueError):
        pass
    if not found:  # pragma: no cover - not Linux
        found.append(float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")))
    return max(min(found), 0.0)


def _node_graph(mesh: TetMesh) -> sp.csr_matrix:
    from .sparsity import NodePattern

    p = NodePattern.of(mesh)
    return sp.csr_matrix((np.ones(p.indices.size), p.indices, p.indptr),
                         shape=(mesh.n_nodes, mesh.n_nodes))


def _estimate(mesh: TetMesh, n_basis: int, factor_entries: int, node_pairs: int,
              method: str) -> MemoryEstimate:
    n = mesh.n_dofs
    k_entries = 9 * node_pairs
    sparse = SPARSE_COPIES * 12.0 * (k_entries + k_entries / 3)
    # basis (n x r) twice (coupled and recovery, float64 before the float32 cast),
    # constraint-mode right-hand sides, the Krylov vectors
    dense = 8.0 * n * (3 * n_basis + KRYLOV_COLUMNS) + FIXED_BYTES
    return MemoryEstimate(n, int(factor_entries), FACTOR_BYTES_PER_ENTRY * factor_entries,
                          sparse, dense, method)


def estimate_memory(mesh: TetMesh, n_basis: int = 40, analyse: bool = True) -> MemoryEstimate:
    """Memory of reducing ``mesh`` onto ``n_basis`` reduced DOFs (boundary + modes).

    ``analyse=False`` (or no PARDISO) gives the closed-form upper bound instead of the
    METIS analysis.

    Examples
    --------
    >>> est = estimate_memory(TetMesh.box((1, .1, .1), (20, 2, 2), order=2), analyse=False)
    >>> est.method, est.total_bytes < 1e9
    ('bound', True)
    """
    n = mesh.n_dofs
    nn = mesh.tets.shape[1]
    pairs_bound = min(mesh.n_nodes**2, mesh.n_tets * nn * nn)
    if analyse:
        from .solvers import available_backends, factor_size

        if "pardiso" in available_backends():
            G = _node_graph(mesh)
            fs = factor_size(G)
            entries = 9 * fs.factor_entries - 3 * mesh.n_nodes
            log.info("factor fill from METIS analysis of %d nodes in %.2f s: %d entries",
                     mesh.n_nodes, fs.seconds, entries)
            return _estimate(mesh, n_basis, entries, G.nnz, "analysis")
    bound = min(FILL_BOUND * n ** (4.0 / 3.0), n * (n + 1) / 2)
    return _estimate(mesh, n_basis, int(bound), pairs_bound, "bound")


def _ranks() -> tuple[int, int]:
    """(MPI ranks, ranks on this host); (1, 1) outside ``mpiexec``."""
    from .petsc_assembly import is_distributed, world

    if not is_distributed():
        return 1, 1
    from mpi4py import MPI

    comm = world()
    host = comm.Split_type(MPI.COMM_TYPE_SHARED)
    return comm.Get_size(), host.Get_size()


def _cluster_hint(est: MemoryEstimate, available: float) -> str:
    hosts = next((n for n in range(2, 65) if est.per_rank_bytes(n) <= available), None)
    if hosts is None:
        return (f"even 64 machines like this one would need {_gb(est.per_rank_bytes(64))} "
                "each: coarsen the mesh or use machines with more memory")
    return (f"reduce it across machines: mpiexec --hostfile hosts -n {hosts} --map-by node "
            f"flexarm reduce ... --backend petsc (at least {hosts} machines like this one, "
            "one rank each)")


def plan_memory(mesh: TetMesh, n_modes: int = 20, backend: str | None = None,
                available: float | None = None, n_boundary: int = 12,
                precision: str | None = None) -> MemoryPlan:
    """The path that fits, or :class:`InsufficientMemoryError` with the figures.

    Parameters
    ----------
    mesh : TetMesh
    n_modes, n_boundary : int
        Reduced DOFs the basis will have (modes, interface DOFs).
    backend : str, optional
        The requested solver backend; ``"petsc"`` checks each host's share.
    available : float, optional
        Memory available on this host [bytes] (default :func:`available_memory`).
    precision : {"double", "single"}, optional
        Precision of the factor; ``None`` picks double when it fits in core, else single
        when that fits (PARDISO or SuperLU backends), else PETSc under ``mpiexec``.

    Examples
    --------
    >>> mesh = TetMesh.box((1, .1, .1), (20, 2, 2), order=2)
    >>> plan_memory(mesh, 10, available=8 * GB).path
    'in-core'
    >>> plan_memory(mesh, 10, available=1e6)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    flexarm.fe.memory_estimate.InsufficientMemoryError: 3075 DOF: about ...
    """
    if precision not in (None, "double", "single"):
        raise ValueError(f"precision must be double or single, got '{precision}'")
    if backend == "petsc" and precision == "single":
        raise ValueError("the PETSc backend factorises in double precision only; "
                         "drop --precision single or the PETSc backend")
    avail = available_memory() if available is None else float(available)
    n_basis = n_modes + n_boundary
    est = estimate_memory(mesh, n_basis, analyse=False)
    if est.total_bytes > BOUND_SHARE * avail:  # the bound is not enough: ask METIS
        est = estimate_memory(mesh, n_basis, analyse=True)
    if backend == "petsc":
        ranks, local = _ranks()
        need = local * est.per_rank_bytes(ranks)
        if need > avail:
            raise InsufficientMemoryError(
                f"{est.text()}; on PETSc with {ranks} rank(s), {local} on this host: "
                f"{_gb(need)} here, {_gb(avail)} available; "
                + _cluster_hint(est, avail))
        return MemoryPlan("petsc", "petsc", est, avail, ranks)
    single = est.in_precision("single")
    can_single = backend in (None, "pardiso", "splu")
    if precision != "single" and est.total_bytes <= avail:
        log.info("memory plan: in core, %s, %s available", est.text(), _gb(avail))
        return MemoryPlan(backend, "in-core", est, avail)
    if precision != "double" and can_single and single.total_bytes <= avail:
        log.info("memory plan: in core, %s, %s available", single.text(), _gb(avail))
        return MemoryPlan(backend, "in-core", single, avail, precision="single")
    ranks, local = _ranks() if backend is None and precision is None else (1, 1)
    if ranks > 1 and local * est.per_rank_bytes(ranks) <= avail:
        log.info("memory plan: PETSc on %d ranks, %s", ranks, est.text())
        return MemoryPlan("petsc", "petsc", est, avail, ranks)
    tried = est.text() if precision == "double" or not can_single else (
        single.text() if precision == "single"
        else f"{est.text()}, {_gb(single.total_bytes)} with a single-precision factor")
    raise InsufficientMemoryError(
        f"{tried}, {_gb(avail)} available on this machine; " + _cluster_hint(est, avail))
