"""The regressors of the residual-structure tests: for each structure that a missing
effect outside the candidate library would leave, the raw columns (n readings, 3
components, k) it adds, and its F test against the rest of the whitened residual.

A family (every series, every joint) is tested member by member and reports the
smallest p-value times the family size (Bonferroni).  Sizes are reported in the units a
user reads: µm, µm per reading, degrees, % of the model's deflections.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["STRUCTURES", "StructureTest", "f_test", "structure_tests", "unit_columns"]

#: Test names and what they mean, in report order.
STRUCTURES = {
    "offsets": "per-series offset",
    "outliers": "isolated outliers",
    "frame": "rotation/scale of the measurement frame",
    "drift": "drift in reading order",
    "tool": "load-linear residual fixed in the tool frame",
    "joint_angle": "compliance changing with a joint angle across series",
    "joint_law": "joint deflection nonlinear in its torque",
}


@dataclass(frozen=True)
class StructureTest:
    """One residual-structure test.

    Attributes
    ----------
    name : str
        Key of :data:`STRUCTURES` (``"drift"``).
    p_value : float
        Family-wise p-value (Bonferroni over joints or series or readings) [-].
    alpha : float
        False-alarm rate: the structure is reported when ``p_value < alpha`` [-].
    where : str
        The member of the family that gave the smallest p-value (``"joint 2"``,
        ``"series P1_+x"``, ``"P1_+x step 4, P2_-z step 7"``), or "".
    size : str
        The fitted size of the structure in physical units ("4.9 µm per reading").
    """

    name: str
    p_value: float
    alpha: float
    where: str = ""
    size: str = ""

    @property
    def found(self) -> bool:
        return bool(self.p_value < self.alpha)

    @property
    def label(self) -> str:
        return STRUCTURES[self.name]

    def line(self) -> str:
        """``drift in reading order: p 3e-12 < 0.001 (4.9 µm per reading)``."""
        rel = "<" if self.found else ">="
        extra = ", ".join(t for t in (self.where, self.size) if t) if self.found else ""
        return (f"{self.label}: p {self.p_value:.2g} {rel} {self.alpha:g}"
                + (f" ({extra})" if extra else ""))


def f_test(r: np.ndarray, G: np.ndarray, dof: float) -> tuple[float, np.ndarray]:
    """p-value of the F test of columns ``G`` (already projected) on residual ``r``, and
    the fitted coefficients."""
    from ..distributions import f_sf

    if G.size == 0 or not np.any(G):
        return 1.0, np.zeros(G.shape[1] if G.ndim == 2 else 0)
    coef, *_ = np.linalg.lstsq(G, r, rcond=1e-10)
    gain = float(np.sum((G @ coef) ** 2))
    k = int(np.linalg.matrix_rank(G, tol=1e-8 * np.abs(G).max()))
    rest = float(r @ r) - gain
    if k == 0 or dof - k <= 0 or rest <= 0:
        return 1.0, coef
    F = (gain / k) / (rest / (dof - k))
    return float(f_sf(F, k, dof - k)), coef


def unit_columns(n: int, rows: np.ndarray, values: np.ndarray | None = None) -> np.ndarray:
    """(n, 3, 3): ``values`` (or 1) on ``rows`` along x, y, z."""
    A = np.zeros((n, 3, 3))
    v = np.ones(len(rows)) if values is None else values
    for c in range(3):
        A[rows, c, c] = v
    return A


def _family(res, dof: float, members):
    """Smallest Bonferroni p over ``members`` (label, raw regressors): p, label,
    coefficients, regressors of the best member."""
    best = (1.0, "", np.zeros(0), None)
    members = list(members)
    for label, A in members:
        p, coef = f_test(res.r, res.columns(A), dof)
        if p < best[0] or not best[1]:
            best = (p, label, coef, A)
    return (min(1.0, best[0] * max(len(members), 1)),) + best[1:]


def _offsets(res, dof, alpha):
    p = res.problem
    n = len(p.is_ref)
    members = [(f"series {p.data.series[g[0]]}", unit_columns(n, g[1:])) for g in p.groups
               if len(g) > 1]
    pv, where, coef, A = _family(res, dof, members)
    size = f"{np.linalg.norm(coef) * 1e6:.0f} µm" if coef.size else ""
    return StructureTest("offsets", pv, alpha, where, size), A


def _frame(res, dof, alpha) -> StructureTest:
    u = res.u
    A = np.stack([np.cross(np.eye(3)[a], u) for a in range(3)] + [u], axis=-1)
    pv, coef = f_test(res.r, res.columns(A), dof)
    size = ""
    if coef.size == 4:
        size = (f"rotation {np.degrees(np.linalg.norm(coef[:3])):.2f} deg, scale "
                f"{100 * coef[3]:.2f} % of the model's deflections")
    return StructureTest("frame", pv, alpha, "", size), A


def _drift(res, dof, alpha):
    n = len(res.problem.is_ref)
    A = unit_columns(n, np.arange(n), np.arange(n, dtype=float))
    pv, coef = f_test(res.r, res.columns(A), dof)
    size = f"{np.linalg.norm(coef) * 1e6:.1f} µm per reading" if coef.size else ""
    return StructureTest("drift", pv, alpha, "", size), A


def _tool(res, dof, alpha):
    from ...robot.effects import TOOL_INDEX
    from ...robot.kinematics import tcp_frame

    p = res.problem
    R = tcp_frame(p.arm.chain, p.data.q)[:, :3, :3]
    cols = []
    for a, b in TOOL_INDEX:
        E = np.zeros((3, 3))
        E[a, b] = E[b, a] = 1.0
        cols.append(np.einsum("nij,jk,nlk,nl->ni", R, E, R, p.dw[:, :3]))
    A = np.stack(cols, axis=-1)
    pv, _ = f_test(res.r, res.columns(A), dof)
    return StructureTest("tool", pv, alpha), A


def _joint_members(p, fn):
    out = []
    for j in range(p.arm.chain.n_joints):
        if not np.any(np.abs(p.J[:, :, j]) > 1e-9):
            continue
        cols = fn(j)
        if cols:
            out.append((f"joint {j + 1}", np.stack([p.J[:, :, j] * c[:, None] for c in cols],
                                                   axis=-1)))
    return out


def _joint_angle(res, dof, alpha):
    p = res.problem
    series_q = p.data.q[p.ref]

    def cols(j):
        angles = np.unique(np.round(series_q[:, j], 6))
        if len(angles) < 2:
            return []
        x = p.data.q[:, j] - angles.mean()
        out = [p.dtau[:, j] * x]
        if len(angles) >= 3:
            out.append(p.dtau[:, j] * x**2)
        return out

    pv, where, _, A = _family(res, dof, _joint_members(p, cols))
    return StructureTest("joint_angle", pv, alpha, where), A


def _joint_law(res, dof, alpha):
    p = res.problem

    def cols(j):
        t = p.tau[:, j] / max(float(np.abs(p.tau[:, j]).max()), 1e-9)
        return [g - g[p.ref] for g in (t * np.abs(t), t**3)]

    pv, where, _, A = _family(res, dof, _joint_members(p, cols))
    return StructureTest("joint_law", pv, alpha, where), A


def structure_tests(res, dof: float, alpha: float):
    """(test, raw regressors of its best member) of every F test, in report order
    (outliers aside).  ``res``: the whitened residual of
    :mod:`flexarm.validation.static.residual_structure` (``r``, ``u``, ``problem``,
    ``columns(A)``)."""
    return [_offsets(res, dof, alpha), _frame(res, dof, alpha), _drift(res, dof, alpha),
            _tool(res, dof, alpha), _joint_angle(res, dof, alpha), _joint_law(res, dof, alpha)]
