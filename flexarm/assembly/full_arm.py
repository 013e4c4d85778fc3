"""The full-FE arm as a model the arm analyses accept (``--model full``).

:class:`FullFEArm` is the arm with unreduced links (:mod:`~flexarm.assembly.full_fe`):
the same joints, base, tool and wrist as the flexible arm, the links as their coupled
FE models.  The analyses of :mod:`~flexarm.assembly.analyses` hand a ``FullFEArm`` to
the functions here: at each pose the sparse system is assembled and factorised once,
and that factorisation serves the TCP compliance, the gravity sag and the shift-invert
eigen-solve of the lowest ``n_modes`` modes (kept per pose, so a report that asks for
several of them at one pose pays once).  The FRF is the modal sum over those modes plus
the static residual of the others (exact at 0 Hz, accurate well below the highest kept
mode).  Tens of thousands of DOF per pose: use it to check a reduced model at a few
poses, not for maps over thousands of poses.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..fe.eigen import modes as fe_modes
from ..fe.eigen import shift_invert
from ..fe.solvers import factorize
from ..fe.typing import ArrayLike, FloatArray
from ..robot.description import Robot
from ..robot.kinematics import link_frames
from .build import BuildOptions, Mesher, build_robot
from .flexible import flexible_arm
from .full_fe import FullFEModel, SparseBody, full_fe_bodies, full_fe_matrices
from .modal import Modes
from .system import ArmModel

__all__ = ["FullFEArm", "full_arm", "full_modes", "full_natural_frequencies",
           "full_tcp_compliance", "full_frf", "full_gravity_sag"]

log = logging.getLogger(__name__)

#: Poses whose factorisation a :class:`FullFEArm` keeps (a report asks for a few at once).
_KEEP_POSES = 4


@dataclass(frozen=True, eq=False)
class _Pose:
    model: FullFEModel
    factor: object
    modes: Modes | None = None


@dataclass(frozen=True, eq=False)
class FullFEArm:
    """The arm with unreduced links.

    Attributes
    ----------
    arm : ArmModel
        Kinematics, joints, base support, tool and wrist (its bodies are not used).
    bodies : tuple of SparseBody
        Each link's coupled FE model in floating-frame coordinates.
    n_modes : int
        Modes computed per pose [-].
    link_damping : float
        Modal damping ratio of the strain energy stored in the links [-].
    backend : str or None
        Sparse solver (default: the package's).
    """

    arm: ArmModel
    bodies: tuple[SparseBody, ...]
    n_modes: int = 12
    link_damping: float = 0.01
    backend: str | None = None
    _poses: dict = field(default_factory=dict, repr=False)

    @property
    def chain(self):
        return self.arm.chain

    @property
    def joints(self):
        return self.arm.joints

    @property
    def joint_names(self):
        return self.arm.joint_names

    @property
    def n_dofs(self) -> int:
        """Independent coordinates of the full model."""
        return self.pose(np.zeros(self.chain.n_joints)).model.n_dofs

    def pose(self, q: ArrayLike) -> _Pose:
        """Assembled and factorised system at pose ``q`` (n,) [rad] (kept for reuse)."""
        q = np.asarray(q, dtype=float)
        key = q.tobytes()
        if key not in self._poses:
            if len(self._poses) >= _KEEP_POSES:
                self._poses.pop(next(iter(self._poses)))
            mdl = full_fe_matrices(self.arm, self.bodies, q)
            self._poses[key] = _Pose(mdl, factorize(mdl.K, backend=self.backend, spd=True))
        return self._poses[key]


def full_arm(robot: Robot, options: BuildOptions = BuildOptions(),  # noqa: B008 (frozen)
             n_modes: int = 12, progress: Callable[[str], None] | None = None,
             mesher: Mesher | None = None) -> FullFEArm:
    """The full-FE arm of ``robot`` with the links' meshes, seats and couplings of
    ``options`` (its method and mode count do not matter); ``mesher`` as for
    :func:`~flexarm.assembly.build.build_robot`.

    Examples
    --------
    The E-model's rigid bodies as sparse bodies give the E-model's compliance:

    >>> from flexarm.assembly import emodel, tcp_compliance
    >>> from flexarm.assembly.full_fe import sparse_bodies
    >>> from flexarm.robot import load_robot
    >>> robot = load_robot()
    >>> arm = emodel(robot, equivalent=False)
    >>> fa = FullFEArm(arm, sparse_bodies(arm))
    >>> q = robot.pose("P1")
    >>> bool(np.allclose(full_tcp_compliance(fa, q), tcp_compliance(arm, q), rtol=1e-9))
    True
    """
    opts = BuildOptions("guyan", 0, options.coupling, options.mesh_size, options.order,
                        options.tcp, options.stiffness_scale).resolved(robot)
    bodies = full_fe_bodies(robot, opts, mesher, progress)
    # joints, base, tool and wrist exactly as the flexible arm (only the bodies differ)
    arm = flexible_arm(robot, opts, build_robot(robot, opts, mesher=mesher, progress=progress))
    return FullFEArm(arm, bodies, n_modes)


def _each_pose(q: ArrayLike, one: Callable[[FloatArray], FloatArray]) -> FloatArray:
    q = np.asarray(q, dtype=float)
    flat = q.reshape(-1, q.shape[-1])
    out = np.array([one(qi) for qi in flat])
    return out.reshape(q.shape[:-1] + out.shape[1:])


def full_tcp_compliance(fa: FullFEArm, q: ArrayLike) -> FloatArray:
    """(..., 6, 6) TCP compliance [m/N, rad/(N m)], base frame, one solve per pose."""

    def one(qi):
        p = fa.pose(qi)
        G = p.model.G_tcp.toarray()
        C = G @ p.factor.solve(G.T)
        return 0.5 * (C + C.T)

    return _each_pose(q, one)


def full_modes(fa: FullFEArm, q: ArrayLike) -> Modes:
    """The lowest ``fa.n_modes`` modes at pose ``q`` (n,) [rad], with the joint energy
    shares and modal damping weighted as in :func:`~flexarm.assembly.analyses.modes`."""
    p = fa.pose(q)
    if p.modes is not None:
        return p.modes
    mdl = p.model
    md = fe_modes(mdl.K, mdl.M, fa.n_modes, eigensolver=shift_invert(0.0, fa.backend),
                  factor=p.factor)
    Phi = md.vectors
    big = np.argmax(np.abs(Phi), axis=0)
    Phi = Phi * np.sign(Phi[big, np.arange(Phi.shape[1])])
    n_s = mdl.springs.shape[0]
    e = Phi[:n_s] * (mdl.springs @ Phi[:n_s])
    total = np.maximum(md.omega2, np.finfo(float).tiny)
    energy = np.array([e[s].sum(axis=0) for s in mdl.joint_slices]) / total
    omega = md.omega
    zeta = np.zeros_like(omega)
    for jm, share in zip(fa.joints, energy, strict=True):
        zeta += share * jm.ratio(omega)
    n_f = mdl.joint_slices[0].start if mdl.joint_slices else 0
    base = e[:n_f].sum(axis=0) / total
    zeta += base * fa.arm.foundation_damping
    zeta += np.clip(1 - energy.sum(axis=0) - base, 0, None) * fa.link_damping
    modes = Modes(md.freq_hz, Phi, mdl.G_tcp @ Phi, zeta, energy,
                  [f"x{i}" for i in range(mdl.n_dofs)])
    fa._poses[np.asarray(q, dtype=float).tobytes()] = _Pose(mdl, p.factor, modes)
    return modes


def full_natural_frequencies(fa: FullFEArm, q: ArrayLike) -> FloatArray:
    """(..., n_modes) lowest natural frequencies [Hz], one eigen-solve per pose."""
    return _each_pose(q, lambda qi: full_modes(fa, qi).freq_hz)


def full_frf(fa: FullFEArm, q: ArrayLike, freq_hz: ArrayLike,
             damping: ArrayLike | None = None) -> np.ndarray:
    """(nf, 6, 6) TCP receptance: the modal sum over the kept modes plus the static
    residual ``C - sum psi psi^T / omega^2`` of the rest (exact at 0 Hz)."""
    md = full_modes(fa, q)
    zeta = md.damping if damping is None else np.broadcast_to(damping, md.freq_hz.shape)
    w = 2 * np.pi * np.asarray(freq_hz, dtype=float)
    wr = md.omega
    psi = md.tcp_shapes
    residual = full_tcp_compliance(fa, q) - (psi / wr**2) @ psi.T
    den = wr[None, :] ** 2 - w[:, None] ** 2 + 2j * zeta * wr[None, :] * w[:, None]
    return np.einsum("ir,fr,jr->fij", psi, 1.0 / den, psi) + residual[None]


def full_gravity_sag(fa: FullFEArm, q: ArrayLike, gravity: ArrayLike) -> FloatArray:
    """(..., 6) TCP displacement [m, rad] under the arm's weight (``gravity`` [m/s^2],
    base frame): each body's weight in its floating frame, one solve per pose."""
    g = np.asarray(gravity, dtype=float)

    def one(qi):
        p = fa.pose(qi)
        F = link_frames(fa.chain, qi)
        f = np.zeros(p.model.n_dofs)
        for i, (b, B) in enumerate(zip(fa.bodies, p.model.body_maps, strict=True)):
            u = np.zeros(b.n_dofs)  # a rigid translation is the joint point's (link frame)
            u[:3] = F[i, :3, :3].T @ g
            f += B.T @ (b.M @ u)
        return p.model.G_tcp @ p.factor.solve(f)

    return _each_pose(q, one)
