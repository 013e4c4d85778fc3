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

from ..fe.files import atomic_path, writes_folder
from ..fe.plotting import picture_from_inputs, pyplot
from ..fe.typing import ArrayLike, FloatArray
from .analyses import natural_frequencies, tcp_compliance
from .system import ArmModel, is_rigid_arm

__all__ = ["JointSpaceMap", "stiffness_map", "limits_map", "stiffest", "write_csv", "plot_map",
           "write_ratio"]

log = logging.getLogger(__name__)
DIRECTIONS = ("x", "y", "z")

#: A grid pose is near a kinematic singularity when the condition number of the TCP's
#: translational Jacobian (3 x n, all columns in m/rad) exceeds this.  There the joints
#: cannot move the TCP along some direction, so that direction's stiffness grows without
#: bound (the links alone carry it) and says nothing about the arm.
SINGULAR_CONDITION = 20.0


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
    condition : (na, nb) float or None
        Condition number [-] of the TCP's translational Jacobian (3 x n) per grid pose.
    label : str
        Model name for titles (``"E-model"``, ``"CB"``...).
    pose_name : str
        Name of the pose the map varies (its other joints are ``q_fixed``).
    collides : (na, nb) bool or None
        Grid poses the robot cannot take: links collide or touch the floor
        (:class:`~flexarm.robot.collision.CollisionChecker`; None: not checked).
    """

    joints: tuple
    a: FloatArray
    b: FloatArray
    q_fixed: FloatArray
    stiffness: FloatArray
    freq_hz: FloatArray | None
    condition: FloatArray | None = None
    label: str = ""
    pose_name: str = ""
    collides: np.ndarray | None = None

    @property
    def is_masked(self) -> np.ndarray:
        """(na, nb) bool: grid poses left out of the stiffest poses and greyed in the
        plots: near a singularity, or colliding."""
        if self.collides is None:
            return self.is_singular
        return self.is_singular | self.collides

    @property
    def is_singular(self) -> np.ndarray:
        """(na, nb) bool: grid poses near a kinematic singularity
        (:data:`SINGULAR_CONDITION`)."""
        if self.condition is None:
            return np.zeros(self.stiffness.shape[:2], dtype=bool)
        return ~(self.condition <= SINGULAR_CONDITION)

    def title(self, field: str) -> str:
        """``"E-model Kxx over (q2, q3) at P1"``: the model, the field and the pose."""
        ja, jb = (j + 1 for j in self.joints)
        if self.pose_name:
            pose = f" at {self.pose_name}"
        else:  # no name: the angles of the joints the map holds fixed
            others = [j for j in range(len(self.q_fixed)) if j not in self.joints]
            pose = ", " + " ".join(f"q{j + 1}={np.degrees(self.q_fixed[j]):.0f}"
                                   for j in others) + " deg" if others else ""
        return f"{self.label or 'arm'} {field} over (q{ja}, q{jb}){pose}"

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
        n_sing = int(self.is_singular.sum())
        if n_sing:
            lines.append(f"{n_sing} of {self.is_singular.size} grid poses lie near a kinematic "
                         f"singularity (TCP Jacobian condition number > "
                         f"{SINGULAR_CONDITION:g}): excluded from the stiffest poses")
        if self.collides is not None and self.collides.any():
            lines.append(f"{int(self.collides.sum())} of {self.collides.size} grid poses "
                         "collide (links with each other or the floor): excluded from the "
                         "stiffest poses")
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
    label: str = "",
    pose_name: str = "",
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
    label, pose_name : str
        Model and pose names for titles (default: ``E-model`` or ``flexible``, no pose).
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
    label = label or ("E-model" if is_rigid_arm(arm) else "flexible")
    return JointSpaceMap(tuple(joints), np.asarray(a, float), np.asarray(b, float),
                         np.asarray(q_fixed, float), K.reshape(shape + (3,)),
                         None if f1 is None else f1.reshape(shape),
                         jacobian_condition(arm, Q), label, pose_name)


def jacobian_condition(arm: ArmModel, Q: ArrayLike) -> FloatArray:
    """(...) condition number [-] of the TCP's translational Jacobian (3 x n) at poses
    ``Q`` (..., n) [rad]; ``inf`` where it loses rank.

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> c = jacobian_condition(two_link_arm(), [[0.0, 0.0], [0.0, 0.5]])
    >>> bool(c[0] > 1e6), bool(c[1] < 1e3)  # stretched: singular; bent: fine
    (True, True)
    """
    from ..robot.kinematics import jacobian

    s = np.linalg.svd(jacobian(arm.chain, Q)[..., :3, :], compute_uv=False)
    with np.errstate(divide="ignore"):
        return s[..., 0] / s[..., -1]


def limits_map(arm: ArmModel, q_fixed: ArrayLike, lower: ArrayLike, upper: ArrayLike,
               n: int = 60, joints=(1, 2), frequencies: bool = True, label: str = "",
               pose_name: str = "") -> JointSpaceMap:
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
    return stiffness_map(arm, q_fixed, a, b, joints, frequencies, label=label,
                         pose_name=pose_name)


def stiffest(m: JointSpaceMap) -> dict:
    """Per direction, the stiffest grid configuration away from kinematic singularities
    and collisions (:attr:`JointSpaceMap.is_masked`): ``{"x": (a, b, K) ...}`` [rad, N/m]."""
    out = {}
    ok = ~m.is_masked if not m.is_masked.all() else np.ones(m.is_masked.shape, bool)
    for d, name in enumerate(DIRECTIONS):
        K = np.where(ok, m.stiffness[..., d], -np.inf)
        i, j = np.unravel_index(np.argmax(K), K.shape)
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
    if m.condition is not None:
        cols += ["jacobian_cond", "near_singular"]
        data += [m.condition.ravel(), m.is_singular.ravel().astype(float)]
    if m.collides is not None:
        cols.append("collides")
        data.append(m.collides.ravel().astype(float))
    lines = [",".join(cols)]
    lines += [",".join(f"{v:.10g}" for v in row) for row in np.column_stack(data)]
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_text("\n".join(lines) + "\n")
    return path


def _heat(ax, m: JointSpaceMap, Z: FloatArray, is_log: bool):
    """One heat map on ``ax``: log colours for stiffness, near-singular poses grey."""
    from matplotlib.colors import LogNorm

    A, B = np.meshgrid(np.degrees(m.a), np.degrees(m.b), indexing="ij")
    Zm = np.ma.masked_where(m.is_masked | ~np.isfinite(Z), Z)
    cmap = pyplot().get_cmap("viridis").with_extremes(bad="0.75")
    norm = LogNorm(vmin=Zm.min(), vmax=Zm.max()) if is_log and Zm.count() else None
    pc = ax.pcolormesh(B, A, Zm, shading="auto", cmap=cmap, norm=norm)
    ja, jb = m.joints
    handles = ax.plot(np.degrees(m.q_fixed[jb]), np.degrees(m.q_fixed[ja]), "r*", ms=12,
                      mec="w", ls="none", label=f"pose {m.pose_name}".strip())
    if m.is_singular.any():
        from matplotlib.patches import Patch

        handles.append(Patch(facecolor="0.75", label=f"near-singular (cond J > "
                                                     f"{SINGULAR_CONDITION:g}), masked"))
    if m.collides is not None and m.collides.any():
        from matplotlib.patches import Patch

        handles.append(Patch(facecolor="0.75", label="colliding, masked"))
    ax.legend(handles=handles, fontsize=7, loc="upper right")
    return pc


@writes_folder()
def plot_map(m: JointSpaceMap, folder, surfaces: bool = True) -> list[Path]:
    """Heat maps and (``surfaces``) 3-D surfaces (PNG) of K_xx, K_yy, K_zz and f1.

    Stiffness is coloured on a log scale (it spans decades near singular poses); poses
    near a kinematic singularity (:attr:`JointSpaceMap.is_singular`) are masked grey and
    left out of the colour range.  Each title names the model and the pose, and a star
    marks the pose the map was varied from.  The numbers are those of :func:`write_csv`.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    fields = [(f"K{d}{d}", m.stiffness[..., i] * 1e-3, "N/mm", True)
              for i, d in enumerate(DIRECTIONS)]
    if m.freq_hz is not None:
        fields.append(("f1", m.freq_hz, "Hz", False))
    out = []
    for name, Z, unit, is_log in fields:
        out.append(_heat_png(folder / f"map_{name}_heat.png", m, name, Z, unit, is_log))
        if surfaces:
            out.append(_surface_png(folder / f"map_{name}_surface.png", m, name, Z, unit,
                                    is_log))
    return out


@picture_from_inputs
def _heat_png(path, m: JointSpaceMap, name: str, Z, unit: str, is_log: bool) -> Path:
    """One heat map of :func:`plot_map`: ``Z`` over the grid of ``m`` in ``unit``."""
    plt = pyplot()
    ja, jb = (j + 1 for j in m.joints)
    fig, ax = plt.subplots(figsize=(6, 4.5))
    pc = _heat(ax, m, Z, is_log)
    fig.colorbar(pc, ax=ax, label=f"{name} [{unit}]" + (" (log scale)" if is_log else ""))
    ax.set_xlabel(f"q{jb} [deg]")
    ax.set_ylabel(f"q{ja} [deg]")
    ax.set_title(m.title(name), fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return Path(path)


@picture_from_inputs
def _surface_png(path, m: JointSpaceMap, name: str, Z, unit: str, is_log: bool) -> Path:
    """One 3-D surface of :func:`plot_map` (masked poses left out)."""
    plt = pyplot()
    ja, jb = (j + 1 for j in m.joints)
    A, B = np.meshgrid(np.degrees(m.a), np.degrees(m.b), indexing="ij")
    fig = plt.figure(figsize=(6, 4.5))
    ax3 = fig.add_subplot(projection="3d")
    Zs = np.where(m.is_masked, np.nan, Z)
    ax3.plot_surface(B, A, np.log10(Zs) if is_log else Zs, cmap="viridis")
    ax3.set_xlabel(f"q{jb} [deg]")
    ax3.set_ylabel(f"q{ja} [deg]")
    ax3.set_zlabel(f"log10 {name} [{unit}]" if is_log else f"{name} [{unit}]")
    what = ("near-singular or colliding" if m.collides is not None and m.collides.any()
            else "near-singular")
    ax3.set_title(m.title(name) + (f" ({what} poses left out)"
                                   if m.is_masked.any() else ""), fontsize=9)
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return Path(path)


@writes_folder()
def write_ratio(flex: JointSpaceMap, rigid: JointSpaceMap, folder) -> list[Path]:
    """How much the flexible links soften the arm: ``K_flex / K_rigid`` per direction on
    the common grid, as ``map_ratio.csv`` (``q<a>_deg, q<b>_deg, kxx_ratio, kyy_ratio,
    kzz_ratio, near_singular`` and ``collides`` when the flexible map has it) and
    ``map_ratio_K<d><d>_heat.png`` (the same numbers; near-singular and colliding poses
    masked) in ``folder``."""
    if flex.stiffness.shape != rigid.stiffness.shape or not (
            np.array_equal(flex.a, rigid.a) and np.array_equal(flex.b, rigid.b)):
        raise ValueError("the two maps must share their grid")
    plt = pyplot()
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        R = flex.stiffness / rigid.stiffness
    ja, jb = (j + 1 for j in flex.joints)
    A, B = np.meshgrid(np.degrees(flex.a), np.degrees(flex.b), indexing="ij")
    cols = [A.ravel(), B.ravel()] + [R[..., d].ravel() for d in range(3)]
    cols.append(flex.is_singular.ravel().astype(float))
    header = f"q{ja}_deg,q{jb}_deg,kxx_ratio,kyy_ratio,kzz_ratio,near_singular"
    if flex.collides is not None:
        cols.append(flex.collides.ravel().astype(float))
        header += ",collides"
    csv = folder / "map_ratio.csv"
    with atomic_path(csv) as tmp:
        np.savetxt(tmp, np.column_stack(cols), delimiter=",", comments="", fmt="%.10g",
                   header=header)
    out = [csv]
    for i, d in enumerate(DIRECTIONS):
        fig, ax = plt.subplots(figsize=(6, 4.5))
        pc = _heat(ax, flex, R[..., i], False)
        fig.colorbar(pc, ax=ax, label=f"K{d}{d} {flex.label} / {rigid.label} [-]")
        ax.set_xlabel(f"q{jb} [deg]")
        ax.set_ylabel(f"q{ja} [deg]")
        ax.set_title(flex.title(f"K{d}{d} / {rigid.label} K{d}{d}"), fontsize=9)
        fig.tight_layout()
        out.append(folder / f"map_ratio_K{d}{d}_heat.png")
        fig.savefig(out[-1], dpi=100)
        plt.close(fig)
    return out
