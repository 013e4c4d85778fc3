"""From a meshed link to a :class:`Superelement`: regions -> coupling -> Guyan/CB.

The regions are selected and checked first (cheap), the matrices assembled and
coupled next, and only then is anything factorised.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..fe.assembly import assemble
from ..fe.files import digest
from ..fe.material import Material
from ..fe.memory_estimate import plan_memory
from ..fe.mesh import TetMesh
from .couplings import Coupling, couple
from .craig_bampton import craig_bampton_blocks, split_system
from .guyan import Reduction, guyan
from .interfaces import Interface, interfaces
from .superelement import (
    FORMAT_VERSION,
    Superelement,
    matrix_mass_properties,
    reduced_rigid_modes,
)

__all__ = ["CoupledModel", "ReductionStats", "coupled_model", "reduce_part", "reduce_with_stats",
           "METHODS"]

log = logging.getLogger(__name__)

METHODS = ("guyan", "cb")


@dataclass(frozen=True, eq=False)
class CoupledModel:
    """The unreduced model with its interfaces coupled (the reference of every study).

    Attributes
    ----------
    K, M : (n_c, n_c) sparse CSR
        Coupled stiffness and mass, master DOFs last.
    coupling : Coupling
    interfaces : tuple of Interface
    K_full, M_full : (3 n_nodes, 3 n_nodes) sparse CSR
        Uncoupled FE matrices.
    """

    K: sp.csr_matrix
    M: sp.csr_matrix
    coupling: Coupling
    interfaces: tuple[Interface, ...]
    K_full: sp.csr_matrix
    M_full: sp.csr_matrix


@dataclass(frozen=True)
class ReductionStats:
    """Sizes and wall times of one reduction.

    Attributes
    ----------
    n_full, n_coupled, n_reduced : int
        DOFs of the FE model (3 per node), after the coupling, of the superelement.
    region_nodes : dict of str -> int
        FE nodes in each interface region.
    seconds : dict of str -> float
        Wall time [s] per step, in order: ``assemble_couple``, the reduction's own
        steps (``factorise``, ``constraint_modes``, ``eigen``, ``projection``), ``total``.
    precision : {"double", "single"}
        Precision of the factor of the interior stiffness (solves are double-accurate).
    """

    n_full: int
    n_coupled: int
    n_reduced: int
    region_nodes: dict
    seconds: dict
    precision: str = "double"

    @property
    def total_seconds(self) -> float:
        """Wall time of the whole reduction [s]."""
        return float(self.seconds["total"])


def coupled_model(mesh: TetMesh, material: Material, regions, coupling: str = "rbe2",
                  n_masters: int | None = None, surface_only: bool = True,
                  matrices=None) -> CoupledModel:
    """Select and check the regions, assemble ``K, M`` and apply the coupling.

    ``matrices`` = ``(K, M)`` reuses an assembly of ``mesh``.
    """
    ifaces = interfaces(mesh, regions, surface_only)  # fails before any heavy work
    K, M = matrices if matrices is not None else assemble(mesh, material)
    c = couple(mesh, ifaces, coupling, n_masters)
    T = c.T
    K_c = (T.T @ K @ T).tocsr()
    M_c = (T.T @ M @ T).tocsr()
    return CoupledModel(K_c, M_c, c, ifaces, sp.csr_matrix(K), sp.csr_matrix(M))


def _surface(mesh: TetMesh):
    faces = mesh.boundary_faces()
    nodes, inv = np.unique(faces, return_inverse=True)
    return mesh.points[nodes], inv.reshape(-1, 3).astype(np.int64), nodes


def reduce_with_stats(mesh: TetMesh, material: Material, regions, coupling: str = "rbe2",
                      method: str = "cb", n_modes: int = 20, n_masters: int | None = None,
                      diagonal: bool = False, surface_only: bool = True,
                      recovery_dtype=np.float32, backend: str | None = None,
                      matrices=None, precision: str | None = None,
                      ) -> tuple[Superelement, ReductionStats]:
    """:func:`reduce_part` that also returns the sizes and wall times of each step.

    ``backend="petsc"`` reduces across the MPI ranks of ``mpiexec -n N`` (every rank calls
    this; ranks other than 0 get ``(None, None)``).  A memory estimate runs first and
    raises :class:`~flexarm.fe.memory_estimate.InsufficientMemoryError` when the link does
    not fit (see :func:`~flexarm.fe.memory_estimate.plan_memory`).  ``precision`` of the
    factor: ``"double"``, ``"single"`` (half the factor's memory, solves refined to
    double accuracy) or ``None``: double when it fits, else single.
    """
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}, got '{method}'")
    n = 0 if method == "guyan" else int(n_modes)
    plan = plan_memory(mesh, n, backend, precision=precision)  # refuses before heavy work
    backend, precision = plan.backend, plan.precision
    t0 = time.perf_counter()
    if backend == "petsc":  # every MPI rank runs this; rank 0 gets the reduction
        from .petsc_backend import reduce_coupled_petsc

        ifaces, c, red, t_asm = reduce_coupled_petsc(mesh, material, regions, coupling, n,
                                                     n_masters, diagonal, surface_only)
        if red is None:
            return None, None
        t1 = t0 + t_asm
    else:
        model = coupled_model(mesh, material, regions, coupling, n_masters, surface_only,
                              matrices)
        ifaces, c = model.interfaces, model.coupling
        # CB needs the coupled K, M only split at the boundary: the full matrices (and
        # the uncoupled ones) are freed before the factor, the largest allocation, is made
        system = split_system(model.K, model.M, c.n_boundary) if n else (model.K, model.M)
        del model
        t1 = time.perf_counter()
        if n:
            red: Reduction = craig_bampton_blocks(system, n, diagonal, backend=backend,
                                                  precision=precision)
        else:
            red = guyan(*system, c.n_boundary, backend=backend, precision=precision)
        del system
    T_full = np.asarray(c.T @ red.T, dtype=recovery_dtype)
    rigid = reduced_rigid_modes(c.node_positions, c.dofs_per_node, red.K.shape[0])
    mp = matrix_mass_properties(red.M, rigid)
    pts, faces, snodes = _surface(mesh)
    key = digest(mesh.points, mesh.tets, (material.E, material.nu, material.rho),
                 repr(tuple(regions)), coupling, method, n, n_masters, diagonal, surface_only,
                 np.dtype(recovery_dtype).str, FORMAT_VERSION)
    se = Superelement(
        K=red.K, M=red.M,
        interface_names=tuple(i.name for i in ifaces),
        interface_positions=np.array([i.position for i in ifaces]),
        interface_frames=np.array([i.frame for i in ifaces]),
        coupling=coupling, method=method,
        node_positions=c.node_positions, node_interface=c.node_interface,
        dofs_per_node=c.dofs_per_node, freq_hz=red.freq_hz,
        mass=mp.mass, center_of_mass=mp.center_of_mass, inertia=mp.inertia,
        input_hash=key, T=T_full, surface_points=pts, surface_faces=faces,
        surface_nodes=snodes,
    )
    stats = ReductionStats(
        mesh.n_dofs, c.n_coupled, red.K.shape[0],
        {i.name: int(i.nodes.size) for i in ifaces},
        {"assemble_couple": t1 - t0, **red.seconds, "total": time.perf_counter() - t0},
        precision)
    log.info("reduced %d -> %d DOF in %.2f s", mesh.n_dofs, red.K.shape[0],
             stats.total_seconds)
    return se, stats


def reduce_part(mesh: TetMesh, material: Material, regions, coupling: str = "rbe2",
                method: str = "cb", n_modes: int = 20, **options) -> Superelement:
    """Reduce a meshed link onto its interfaces.

    Parameters
    ----------
    mesh : TetMesh
        The link in its own frame [m].
    material : Material
    regions : sequence of CylinderRegion or NodeSetRegion
        One per interface, in the order the superelement's DOFs will have.
    coupling : {"rbe2", "rbe3", "nodes"}
    method : {"guyan", "cb"}
    n_modes : int
        Fixed-interface modes for Craig-Bampton.
    **options
        ``n_masters`` (k kept nodes for ``coupling="nodes"``), ``diagonal``,
        ``surface_only``, ``recovery_dtype``, ``backend``, ``matrices``, ``precision``.

    Examples
    --------
    >>> from flexarm.fe.material import MATERIALS
    >>> from flexarm.reduction.interfaces import CylinderRegion
    >>> mesh = TetMesh.box((1.0, 0.1, 0.1), (8, 1, 1))
    >>> ends = [CylinderRegion(n, (x, .05, .05), (1, 0, 0), 0, 1, 1e-3)
    ...         for n, x in (("a", 0.0), ("b", 1.0))]
    >>> se = reduce_part(mesh, MATERIALS["steel"], ends, "rbe2", "cb", 4)
    >>> se.n_dofs, round(se.mass, 6)
    (16, 78.5)
    """
    return reduce_with_stats(mesh, material, regions, coupling, method, n_modes, **options)[0]
