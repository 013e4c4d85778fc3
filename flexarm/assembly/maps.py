"""Joint-space maps: TCP axial stiffness and first eigenfrequency over two joints.

The axial stiffness ``K_ii = 1 / C_ii`` is the inverse static gain of a unit TCP
force in base direction ``i`` (thesis eq. 3.9).  All poses are evaluated in one
batched call; the assembled stiffness of rigid and floating-frame flexible arms does not
depend on the pose (:mod:`~flexarm.assembly.batched`), so a 100×100 grid of TCP
compliance takes a fraction of a second for the E-model and the flexible model alike;
the first eigenfrequency needs one eigen-solve per pose (a few hundred poses/s flexible).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..fe.files import atomic_path
from ..fe.plotting import pyplot
from ..fe.typing import ArrayLike, FloatArray
from .analyses import natural_frequencies, tcp_compliance
from .system import ArmModel

__all__ = ["JointSpaceMap", "stiffness_map", "limits_map", "stiffest", "write_csv", "plot_map"]

log = logging.getLogger(__name__)
DIRECTIONS = ("x", "y", "z")


@dataclass(frozen=True)
class JointSpaceMap:
    """TCP stiffness over a grid of two joints (the others fixed).

    Attributes
    ----------
    joints : (2,) int
        Indices of the two varied joints (0-based).
    a, b : (na,), (nb,) float
        Grid angles of the two joints [rad].
    q_fixed : (n,) float
        The other joints' angles [rad].
    stiffness : (na, nb, 3) float
        Axial TCP stiffness K_xx, K_yy, K_zz [N/m] (base frame).
    freq_hz : (na, nb) float or None
        First eigenfrequency [Hz].
    """

    joints: tuple
    a: FloatArray
    b: FloatArray
    q_fixed: FloatArray
    stiffness: FloatArray
    freq_hz: FloatArray | None

    @property
    def least_stiff(self) -> np.ndarray:
        """(na, nb) int: index (0=x, 1=y, 2=z) of the least stiff direction."""
        return np.argmin(self.stiffness, axis=-1)

    @property
    def least_stiff_share(self) -> FloatArray:
        """(3,) share of the grid [-] on which x, y, z is the least stiff direction."""
        return np.bincount(self.least_stiff.ravel(), minlength=3) / self.least_stiff.size

    def summary(self) -> str:
        """Least-stiff shares and the stiffest configuration per direction (text)."""
        lines = ["least stiff direction share: " + "  ".join(
            f"{d}={s * 100:.1f}%" for d, s in zip(DIRECTIONS, self.least_stiff_share,
                                                 strict=True))]
        for d, (a, b, k) in stiffest(self).items():
            lines.append(f"stiffest in {d}: q{self.joints[0] + 1}={np.degrees(a):7.1f} deg "
                         f"q{self.joints[1] + 1}={np.degrees(b):7.1f} deg "
                         f"K{d}{d}={k * 1e-3:.0f} N/mm")
        return "\n".join(lines)


def grid_poses(q_fixed: ArrayLike, joints, a: ArrayLike, b: ArrayLike) -> FloatArray:
    """(na, nb, n) poses [rad] varying ``joints`` over ``a`` × ``b``."""
    q = np.asarray(q_fixed, dtype=float)
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    Q = np.broadcast_to(q, (len(a), len(b), len(q))).copy()
    Q[..., joints[0]] = a[:, None]
    Q[..., joints[1]] = b[None, :]
    return Q


def stiffness_map(
    arm: ArmModel,
    q_fixed: ArrayLike,
    a: ArrayLike,
    b: ArrayLike,
    joints=(1, 2),
    frequencies: bool = True,
    chunk: int = 20000,
) -> JointSpaceMap:
    """Evaluate the TCP axial stiffness (and first frequency) on a joint grid.

    Parameters
    ----------
    arm : ArmModel
    q_fixed : (n,) float
        Angles [rad] of the joints not varied.
    a, b : (na,), (nb,) float
        Angles [rad] of ``joints[0]`` and ``joints[1]`` (default joints 2 and 3).
    frequencies : bool
        Also compute the first eigenfrequency (a batched eigen-solve per pose).
    chunk : int
        Poses per batched call (bounds memory; ``M(q)`` is assembled 50 poses at a time).
    """
    Q = grid_poses(q_fixed, joints, a, b)
    flat = Q.reshape(-1, Q.shape[-1])
    log.info("stiffness map over %d poses", len(flat))
    K = np.zeros((len(flat), 3))
    f1 = np.zeros(len(flat)) if frequencies else None
    for s in range(0, len(flat), chunk):
        C = tcp_compliance(arm, flat[s : s + chunk])
        with np.errstate(divide="ignore"):  # a direction the joints cannot move: K = inf
            K[s : s + chunk] = 1.0 / np.einsum("mii->mi", C[:, :3, :3])
        if frequencies:
            f1[s : s + chunk] = natural_frequencies(arm, flat[s : s + chunk])[:, 0]
    log.info("stiffness map done")
    shape = Q.shape[:2]
    return JointSpaceMap(tuple(joints), np.asarray(a, float), np.asarray(b, float),
                         np.asarray(q_fixed, float), K.reshape(shape + (3,)),
                         None if f1 is None else f1.reshape(shape))


def limits_map(arm: ArmModel, q_fixed: ArrayLike, lower: ArrayLike, upper: ArrayLike,
               n: int = 60, joints=(1, 2), frequencies: bool = True) -> JointSpaceMap:
    """:func:`stiffness_map` on an ``n`` x ``n`` grid spanning the two joints' limits
    ``lower``, ``upper`` (n,) [rad].

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> m = limits_map(two_link_arm(), [0.0, 0.0], [-1.0, -1.0], [1.0, 1.0], n=3,
    ...                joints=(0, 1), frequencies=False)
    >>> m.stiffness.shape
    (3, 3, 3)
    """
    if n < 2:
        raise ValueError(f"a map needs at least 2 grid points per joint, got {n}")
    lo, hi = np.asarray(lower, float), np.asarray(upper, float)
    a, b = (np.linspace(lo[j], hi[j], n) for j in joints)
    return stiffness_map(arm, q_fixed, a, b, joints, frequencies)


def stiffest(m: JointSpaceMap) -> dict:
    """Per direction, the stiffest grid configuration: ``{"x": (a, b, K) ...}`` [rad, N/m]."""
    out = {}
    for d, name in enumerate(DIRECTIONS):
        i, j = np.unravel_index(np.argmax(m.stiffness[..., d]), m.stiffness.shape[:2])
        out[name] = (float(m.a[i]), float(m.b[j]), float(m.stiffness[i, j, d]))
    return out


def write_csv(path, m: JointSpaceMap) -> Path:
    """Write the map as CSV with unit-suffixed columns (DESIGN §3)."""
    ja, jb = (j + 1 for j in m.joints)
    cols = [f"q{ja}_deg", f"q{jb}_deg", "kxx_N_per_mm", "kyy_N_per_mm", "kzz_N_per_mm"]
    A, B = np.meshgrid(np.degrees(m.a), np.degrees(m.b), indexing="ij")
    data = [A.ravel(), B.ravel()] + [m.stiffness[..., d].ravel() * 1e-3 for d in range(3)]
    if m.freq_hz is not None:
        cols.append("f1_Hz")
        data.append(m.freq_hz.ravel())
    lines = [",".join(cols)]
    lines += [",".join(f"{v:.10g}" for v in row) for row in np.column_stack(data)]
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_text("\n".join(lines) + "\n")
    return path


def plot_map(m: JointSpaceMap, folder, surfaces: bool = True) -> list[Path]:
    """Heat maps and (``surfaces``) 3-D surfaces (PNG) of K_xx, K_yy, K_zz and f1."""
    plt = pyplot()

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    ja, jb = (j + 1 for j in m.joints)
    A, B = np.meshgrid(np.degrees(m.a), np.degrees(m.b), indexing="ij")
    fields = [(f"K{d}{d}", m.stiffness[..., i] * 1e-3, "N/mm") for i, d in enumerate(DIRECTIONS)]
    if m.freq_hz is not None:
        fields.append(("f1", m.freq_hz, "Hz"))
    out = []
    for name, Z, unit in fields:
        fig, ax = plt.subplots(figsize=(6, 4.5))
        pc = ax.pcolormesh(B, A, Z, shading="auto", cmap="viridis")
        fig.colorbar(pc, ax=ax, label=f"{name} [{unit}]")
        ax.set_xlabel(f"q{jb} [deg]")
        ax.set_ylabel(f"q{ja} [deg]")
        ax.set_title(f"{name} over (q{ja}, q{jb})")
        p = folder / f"map_{name}_heat.png"
        fig.savefig(p, dpi=100)
        plt.close(fig)
        out.append(p)
        if not surfaces:
            continue
        fig = plt.figure(figsize=(6, 4.5))
        ax3 = fig.add_subplot(projection="3d")
        ax3.plot_surface(B, A, Z, cmap="viridis")
        ax3.set_xlabel(f"q{jb} [deg]")
        ax3.set_ylabel(f"q{ja} [deg]")
        ax3.set_zlabel(f"{name} [{unit}]")
        p3 = folder / f"map_{name}_surface.png"
        fig.savefig(p3, dpi=100)
        plt.close(fig)
        out.append(p3)
    return out
