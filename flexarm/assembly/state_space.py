"""The arm at a pose as a linear state-space model (``A, B, C, D``) in modal coordinates.

Inputs (base frame): the TCP wrench ``tcp_Fx .. tcp_Mz`` [N, N m] and each joint's drive
torque ``<joint>_torque`` [N m], a torque pair between parent and child about the joint
axis (its virtual work is the torque times the joint's torsional deflection).  Outputs:
the TCP motion ``tcp_ux .. tcp_rz`` [m, rad] and every elastic joint deflection
``<joint>_<dof>`` (torsion, bearing tilt [rad]; radial, axial [m]).

The realisation is the arm's own modal superposition, so it reproduces
:func:`~flexarm.assembly.analyses.frf` term by term: mode ``r`` (mass-normalised shape
``phi_r``, ``omega_r`` [rad/s], ratio ``zeta_r``) has the states ``(omega_r eta_r,
d eta_r / dt)`` and the 2x2 block ``[[0, omega_r], [-omega_r, -2 zeta_r omega_r]]``;
``B`` holds ``phi_r^T b`` in the velocity row, ``C`` holds ``c phi_r / omega_r`` in the
displacement column.  Scaling the displacement state by ``omega_r`` keeps every block's
norm near ``omega_r``, so the poles ``-zeta omega +- i omega sqrt(1 - zeta^2)`` come out
of a general eigen-solver to full relative accuracy.  When only the lowest ``n_modes``
are kept (and always for the full-FE arm) ``D`` is the static residual of the others,
``c K^-1 b - sum_r c phi_r phi_r^T b / omega_r^2``, so the DC gain stays the static
compliance exactly.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from ..fe.typing import ArrayLike, FloatArray
from ..robot.joints import DOF_NAMES
from .analyses import modes
from .full_arm import FullFEArm, full_modes
from .system import ArmModel, system_matrices

__all__ = ["ArmStateSpace", "state_space", "to_arrays", "from_arrays", "TCP_INPUTS",
           "TCP_OUTPUTS"]

log = logging.getLogger(__name__)

#: TCP wrench inputs (base frame) and their units.
TCP_INPUTS = (("tcp_Fx", "N"), ("tcp_Fy", "N"), ("tcp_Fz", "N"),
              ("tcp_Mx", "N m"), ("tcp_My", "N m"), ("tcp_Mz", "N m"))
#: TCP motion outputs (base frame) and their units.
TCP_OUTPUTS = (("tcp_ux", "m"), ("tcp_uy", "m"), ("tcp_uz", "m"),
               ("tcp_rx", "rad"), ("tcp_ry", "rad"), ("tcp_rz", "rad"))
_DOF_UNITS = ("m", "m", "m", "rad", "rad", "rad")


@dataclass(frozen=True, eq=False)
class ArmStateSpace:
    """``dx/dt = A x + B u``, ``y = C x + D u`` of the arm at one pose (SI units).

    Attributes
    ----------
    A : (2 n_m, 2 n_m) float
        Block diagonal, one 2x2 block per mode [1/s].
    B : (2 n_m, n_in) float
    C : (n_out, 2 n_m) float
    D : (n_out, n_in) float
        Static residual of the modes left out [m/N, ...] (zero when all are kept).
    input_names, input_units, output_names, output_units, state_names : tuple of str
    omega : (n_m,) float
        Natural angular frequencies [rad/s], ascending.
    damping : (n_m,) float
        Modal damping ratios [-] (as in :func:`~flexarm.assembly.analyses.modes`).
    input_participation : (n_m, n_in) float
        Modal force of a unit input on the mass-normalised modal coordinate,
        ``phi_r^T b``.
    output_participation : (n_out, n_m) float
        Output per unit mass-normalised modal coordinate, ``c phi_r``; the modal
        receptance of input ``k`` at output ``i`` is ``c_ir b_rk / omega_r^2`` [m/N, ...].
    q : (n,) float
        The pose [rad].
    model : str
        The arm model's label (``E-model``, ``CB``, ...).
    """

    A: FloatArray
    B: FloatArray
    C: FloatArray
    D: FloatArray
    input_names: tuple[str, ...]
    input_units: tuple[str, ...]
    output_names: tuple[str, ...]
    output_units: tuple[str, ...]
    state_names: tuple[str, ...]
    omega: FloatArray
    damping: FloatArray
    input_participation: FloatArray
    output_participation: FloatArray
    q: FloatArray
    model: str = ""

    @property
    def freq_hz(self) -> FloatArray:
        """(n_m,) natural frequencies [Hz]."""
        return self.omega / (2 * np.pi)

    @property
    def n_modes(self) -> int:
        return int(self.omega.size)

    def poles(self) -> np.ndarray:
        """(2 n_m,) complex poles from the modal data [1/s]: ``-zeta omega +- i omega_d``,
        mode by mode (upper half-plane first); overdamped modes give two real poles."""
        w, z = self.omega, self.damping
        root = np.sqrt((z**2 - 1).astype(complex))
        return np.column_stack([-z * w + w * root, -z * w - w * root]).ravel()

    def frequency_response(self, freq_hz: ArrayLike, chunk: int = 32) -> np.ndarray:
        """(nf, n_out, n_in) complex ``C (i omega I - A)^-1 B + D`` at ``freq_hz`` [Hz],
        from the matrices alone (batched dense solves, ``chunk`` frequencies at a time)."""
        f = np.atleast_1d(np.asarray(freq_hz, dtype=float))
        eye = np.eye(self.A.shape[0])
        out = np.zeros((f.size,) + self.D.shape, dtype=complex)
        for s in range(0, f.size, chunk):  # bounds memory: chunk x n_states^2 complex
            s_i = 2j * np.pi * f[s : s + chunk, None, None]
            rhs = np.broadcast_to(self.B, (s_i.shape[0],) + self.B.shape)
            out[s : s + chunk] = self.C @ np.linalg.solve(s_i * eye - self.A, rhs) + self.D
        return out

    def dc_gain(self) -> FloatArray:
        """(n_out, n_in) static gain ``D - C A^-1 B`` [m/N, ...]."""
        return self.D - self.C @ np.linalg.solve(self.A, self.B)

    def index(self, names, kind: str = "input") -> list[int]:
        """Positions of ``names`` among the inputs (``kind="input"``) or outputs."""
        have = self.input_names if kind == "input" else self.output_names
        missing = [n for n in names if n not in have]
        if missing:
            raise ValueError(f"no {kind} named {', '.join(missing)} (have: {', '.join(have)})")
        return [have.index(n) for n in names]

    def text(self, n: int = 10) -> str:
        """Sizes, names and the first ``n`` modes (frequency [Hz], damping ratio)."""
        lines = [f"{self.model} state-space model: {self.A.shape[0]} states "
                 f"({self.n_modes} modes), {len(self.input_names)} inputs, "
                 f"{len(self.output_names)} outputs; SI units",
                 "inputs:  " + ", ".join(f"{a} [{u}]" for a, u in
                                         zip(self.input_names, self.input_units, strict=True)),
                 "outputs: " + ", ".join(f"{a} [{u}]" for a, u in
                                         zip(self.output_names, self.output_units, strict=True)),
                 f"{'mode':>4s} {'freq_Hz':>10s} {'zeta':>7s}"]
        lines += [f"{r + 1:4d} {f:10.3f} {z:7.4f}" for r, (f, z) in
                  enumerate(zip(self.freq_hz[:n], self.damping[:n], strict=True))]
        if self.n_modes > n:
            lines.append(f"... {self.n_modes - n} more modes up to {self.freq_hz[-1]:.0f} Hz")
        return "\n".join(lines)


def _ports(joint_names, joints, joint_cols, n_x: int):
    """Joint-torque input columns and joint-deflection output rows on the coordinates.

    ``joint_cols[j]`` are joint ``j``'s coordinates, one per free DOF of its model.
    """
    inputs, in_names, out_rows, out_names, out_units = [], [], [], [], []
    for name, jm, cols in zip(joint_names, joints, joint_cols, strict=True):
        for col, d in zip(cols, jm.free_dofs, strict=True):
            e = np.zeros(n_x)
            e[col] = 1.0
            out_rows.append(e)
            out_names.append(f"{name}_{DOF_NAMES[d]}")
            out_units.append(_DOF_UNITS[d])
            if d == 3:  # a drive torque works on the torsional deflection
                inputs.append(e)
                in_names.append(f"{name}_torque")
    return inputs, in_names, out_rows, out_names, out_units


def _realisation(Phi, omega, zeta, Bp, Cp):
    """``A, B, C`` of the scaled modal states (see the module docstring)."""
    n = omega.size
    if np.any(omega <= 0):
        raise ValueError("a state-space model needs a supported arm: it has a rigid-body "
                         "mode (omega = 0)")
    A = np.zeros((2 * n, 2 * n))
    r = np.arange(n)
    A[2 * r, 2 * r + 1] = omega
    A[2 * r + 1, 2 * r] = -omega
    A[2 * r + 1, 2 * r + 1] = -2 * zeta * omega
    b = Phi.T @ Bp
    c = Cp @ Phi
    B = np.zeros((2 * n, Bp.shape[1]))
    B[2 * r + 1] = b
    C = np.zeros((Cp.shape[0], 2 * n))
    C[:, 2 * r] = c / omega
    return A, B, C, b, c


def state_space(arm: ArmModel | FullFEArm, q: ArrayLike, n_modes: int | None = None,
                model: str = "") -> ArmStateSpace:
    """The arm at pose ``q`` (n,) [rad] as an :class:`ArmStateSpace` with its modal damping.

    ``n_modes``: keep only the lowest modes and put the static residual of the rest in
    ``D`` (None: every mode of a reduced arm, ``D = 0``; the full-FE arm's computed modes
    plus residual).

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> from flexarm.assembly.analyses import tcp_compliance
    >>> ss = state_space(two_link_arm(), [0.0, 0.5])
    >>> ss.A.shape, ss.input_names[-1], ss.output_names[-1]
    ((4, 4), 'joint_2_torque', 'joint_2_torsion')
    >>> C = tcp_compliance(two_link_arm(), [0.0, 0.5])
    >>> bool(np.allclose(ss.dc_gain()[:6, :6], C, rtol=1e-12, atol=1e-12 * abs(C).max()))
    True
    """
    q = np.asarray(q, dtype=float)
    if isinstance(arm, FullFEArm):
        pose = arm.pose(q)
        md = full_modes(arm, q)
        G = pose.model.G_tcp.toarray()
        n_x = pose.model.n_dofs
        cols = [np.arange(s.start, s.stop) for s in pose.model.joint_slices]
        solve = pose.factor.solve
        joints, names = arm.joints, arm.joint_names
    else:
        md = modes(arm, q)
        sm = system_matrices(arm, q)
        G = sm.G_tcp
        n_x = arm.layout["n"]
        cols = arm.layout["joint"]
        K = sm.K
        solve = (lambda rhs: np.linalg.solve(K, rhs))  # noqa: E731 - one closure per model
        joints, names = arm.joints, arm.joint_names
    j_in, j_in_names, j_out, j_out_names, j_out_units = _ports(names, joints, cols, n_x)
    Bp = np.column_stack([G.T] + [e[:, None] for e in j_in])
    Cp = np.vstack([G] + [e[None, :] for e in j_out])
    keep = md.freq_hz.size if n_modes is None else min(int(n_modes), md.freq_hz.size)
    if keep < 1:
        raise ValueError(f"n_modes must be >= 1, got {n_modes}")
    Phi, omega, zeta = md.shapes[:, :keep], md.omega[:keep], md.damping[:keep]
    truncated = isinstance(arm, FullFEArm) or keep < md.freq_hz.size
    D = np.zeros((Cp.shape[0], Bp.shape[1]))
    A, B, C, b, c = _realisation(Phi, omega, zeta, Bp, Cp)
    if truncated:  # static residual of the modes left out: DC gain stays exact
        D = Cp @ solve(Bp) - (c / omega**2) @ b
    states = tuple(s for r in range(keep) for s in (f"mode_{r + 1}_omega_eta",
                                                      f"mode_{r + 1}_eta_dot"))
    log.info("state space: %d modes, %d inputs, %d outputs", keep, Bp.shape[1], Cp.shape[0])
    return ArmStateSpace(
        A, B, C, D,
        tuple(n for n, _ in TCP_INPUTS) + tuple(j_in_names),
        tuple(u for _, u in TCP_INPUTS) + ("N m",) * len(j_in_names),
        tuple(n for n, _ in TCP_OUTPUTS) + tuple(j_out_names),
        tuple(u for _, u in TCP_OUTPUTS) + tuple(j_out_units),
        states, omega, zeta, b, c, q, model)


#: Text fields of a state-space file (everything else is a float array).
_NAME_FIELDS = ("input_names", "input_units", "output_names", "output_units", "state_names")
_ARRAY_FIELDS = ("A", "B", "C", "D", "omega", "damping", "input_participation",
                 "output_participation")


def to_arrays(ss: ArmStateSpace) -> dict:
    """Every field as arrays (names as str arrays), plus ``freq_hz``, ``q_rad``, ``units``
    and a ``description`` line, for the file formats."""
    d = {k: np.asarray(getattr(ss, k), dtype=float) for k in _ARRAY_FIELDS}
    d.update({k: list(getattr(ss, k)) for k in _NAME_FIELDS})
    d["freq_hz"] = ss.freq_hz
    d["q_rad"] = np.asarray(ss.q, dtype=float)
    d["model"] = ss.model
    d["units"] = "SI"
    d["description"] = (f"flexarm {ss.model} arm at q = {np.round(np.degrees(ss.q), 6).tolist()}"
                        " deg: dx/dt = A x + B u, y = C x + D u; states (omega_r eta_r, "
                        "d eta_r/dt) per mode r (mass-normalised eta); SI units (N, N m, m, "
                        "rad, s); TCP inputs and outputs in the robot base frame")
    return d


def from_arrays(d: dict, where: str = "state-space file") -> ArmStateSpace:
    """The :class:`ArmStateSpace` of :func:`to_arrays` (``where`` names the source in
    errors); checks the shapes."""
    from ..fe.errors import ReadError

    missing = [k for k in _ARRAY_FIELDS + _NAME_FIELDS + ("q_rad",) if k not in d]
    if missing:
        raise ReadError(f"{where}: missing field(s) {', '.join(missing)}")
    a = {k: np.asarray(d[k], dtype=float) for k in _ARRAY_FIELDS}
    names = {k: tuple(str(s) for s in d[k]) for k in _NAME_FIELDS}
    n, n_in, n_out = a["A"].shape[0], len(names["input_names"]), len(names["output_names"])
    want = {"A": (n, n), "B": (n, n_in), "C": (n_out, n), "D": (n_out, n_in),
            "omega": (n // 2,), "damping": (n // 2,), "input_participation": (n // 2, n_in),
            "output_participation": (n_out, n // 2)}
    for k, shape in want.items():
        if a[k].shape != shape:
            raise ReadError(f"{where}: field {k} must be {shape}, got {a[k].shape}")
    return ArmStateSpace(**a, **names, q=np.asarray(d["q_rad"], dtype=float).ravel(),
                         model=str(d.get("model", "")))
