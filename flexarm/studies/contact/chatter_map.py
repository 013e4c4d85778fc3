"""Limit cutting stiffness ``K_c b`` in closed form, and its map over joints 2 and 3.

Every coefficient of ``p(s) = det(M s^2 + C s + K + k f n^T)`` is affine in ``k``
(rank-one process stiffness): ``a_i(k) = alpha_i + k beta_i``.  Stability is lost
where a real root crosses ``s = 0`` (``a0(k) = 0``) or a complex pair crosses the
imaginary axis (Hurwitz determinant ``a1 (a2 a3 - a1 a4) - a0 a3^2 = 0``, a cubic in
``k``).  The limit ``K_c b`` is the smallest positive such root above which the
Routh–Hurwitz test fails; ``inf`` when none does.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...assembly.system import ArmModel
from ...fe.files import atomic_path
from ...fe.typing import ArrayLike, FloatArray
from ..tolerances import tol
from .chatter import char_poly, is_stable, process_vectors
from .plane_batch import plane_matrices

__all__ = ["critical_kcb", "worst_normal", "ChatterMap", "chatter_map", "chatter_limits_map",
           "recommendation"]

log = logging.getLogger(__name__)

#: Poses this close to a joint limit are mapped but never recommended: a robot cannot
#: work there (no room for the path or the wrist to move) [rad].
LIMIT_MARGIN = np.radians(5.0)


def _pmul(p: FloatArray, q: FloatArray) -> FloatArray:
    """Batched polynomial product (coefficients highest power first, last axis)."""
    out = np.zeros(p.shape[:-1] + (p.shape[-1] + q.shape[-1] - 1,))
    for i in range(p.shape[-1]):
        out[..., i:i + q.shape[-1]] += p[..., i:i + 1] * q
    return out


def _cubic_roots(c: FloatArray) -> FloatArray:
    """(..., 3) complex roots of ``c0 k^3 + c1 k^2 + c2 k + c3`` (batched companion matrix)."""
    flat = c.reshape(-1, 4)
    out = np.full((len(flat), 3), np.nan + 0j)
    lead = np.abs(flat[:, 0]) > np.finfo(float).eps * np.abs(flat).max(axis=1)
    if lead.any():
        m = flat[lead, 1:] / flat[lead, :1]
        comp = np.zeros((int(lead.sum()), 3, 3))
        comp[:, 0, :] = -m
        comp[:, 1, 0] = comp[:, 2, 1] = 1.0
        out[lead] = np.linalg.eigvals(comp)
    rest = np.flatnonzero(~lead)  # degenerate leading term: a quadratic (or linear)
    if rest.size:
        c1, c2, c3 = flat[rest, 1], flat[rest, 2], flat[rest, 3]
        quad = np.abs(c1) > np.finfo(float).eps * np.abs(flat[rest]).max(axis=1)
        comp = np.zeros((int(quad.sum()), 2, 2))
        comp[:, 0, 0], comp[:, 0, 1] = -c2[quad] / c1[quad], -c3[quad] / c1[quad]
        comp[:, 1, 0] = 1.0
        out[rest[quad], :2] = np.linalg.eigvals(comp)
        lin = ~quad & (c2 != 0)
        out[rest[lin], 0] = -c3[lin] / c2[lin]
    return out.reshape(c.shape[:-1] + (3,))


def critical_kcb(M: ArrayLike, C: ArrayLike, K: ArrayLike, n: ArrayLike,
                 f: ArrayLike) -> FloatArray:
    """(...) limit process stiffness ``K_c b`` [N/m] (batched over leading axes).

    Parameters
    ----------
    M, C, K : (..., 2, 2) float
        Structure in the plane.
    n, f : (..., 2) float
        Unit surface normal and force direction in the plane axes.

    Returns
    -------
    (...) float
        0 if unstable without cutting, ``inf`` if never unstable for ``k > 0``.

    Examples
    --------
    >>> from flexarm.studies.contact.chatter import cnc_model, process_vectors
    >>> m = cnc_model([1e5, 1.3e5], 50.0, 0.01)
    >>> n, f = process_vectors(-20.0, 30.0)  # weak axis e1 between normal and force
    >>> bool(0 < critical_kcb(m.M, m.C, m.K, n, f) < 1e6)
    True
    """
    M, C, K = (np.asarray(a, dtype=float) for a in (M, C, K))
    nf = np.asarray(f, float)[..., :, None] * np.asarray(n, float)[..., None, :]
    alpha = char_poly(M, C, K)
    beta = char_poly(M, C, K + nf) - alpha
    alpha, beta = np.broadcast_arrays(alpha, beta)
    a = np.stack([beta, alpha], axis=-1)  # (..., 5, 2): a_i(k) highest power first
    a4, a3, a2, a1, a0 = (a[..., i, :] for i in range(5))
    d2 = _pmul(a3, a2) - _pmul(a4, a1)
    d3 = _pmul(a1, d2) - _pmul(_pmul(a0, a3), a3)
    with np.errstate(divide="ignore", invalid="ignore"):
        lin = (-a0[..., 1] / a0[..., 0])[..., None]
    cand = np.concatenate([lin + 0j, _cubic_roots(d3)], axis=-1)
    real = np.where((np.abs(cand.imag) <= 1e-9 * np.abs(cand)) & (cand.real > 0), cand.real,
                    np.inf)
    real = np.sort(real, axis=-1)
    probe = np.where(np.isfinite(real), real * (1 + tol.chatter_limit_probe), 0.0)
    unstable = ~is_stable(alpha[..., None, :] + probe[..., None] * beta[..., None, :])
    unstable &= np.isfinite(real)
    first = np.where(unstable.any(axis=-1), np.take_along_axis(
        real, np.argmax(unstable, axis=-1)[..., None], axis=-1)[..., 0], np.inf)
    return np.where(is_stable(alpha), first, 0.0)


def worst_normal(M, C, K, dir_deg: float, n_angles: int = 72) -> tuple[FloatArray, FloatArray]:
    """Smallest limit ``K_c b`` [N/m] over surface-normal angles in the plane, and that angle [deg].

    The force keeps its angle ``dir_deg`` to the normal.  Batched over leading axes.
    """
    ang = np.arange(n_angles) * 180.0 / n_angles  # n and -n with -f are the same process
    vecs = [process_vectors(a, dir_deg) for a in ang]
    n = np.array([v[0] for v in vecs])
    f = np.array([v[1] for v in vecs])
    M, C, K = (np.asarray(x, float)[..., None, :, :] for x in (M, C, K))
    kc = critical_kcb(M, C, K, n, f)
    i = np.argmin(kc, axis=-1)
    return np.take_along_axis(kc, i[..., None], axis=-1)[..., 0], ang[i]


@dataclass(frozen=True, eq=False)
class ChatterMap:
    """Limit ``K_c b`` over a (q2, q3) grid.

    Attributes
    ----------
    q2, q3 : (n2,), (n3,) float
        Grid angles [rad].
    kcb : (n2, n3) float
        Limit process stiffness [N/m] (NaN where out of reach of the joint limits).
    normal_deg : (n2, n3) float
        Surface-normal angle used (worst case, or the given one) [deg].
    k_weak : (n2, n3) float
        Weakest in-plane principal stiffness [N/m].
    dir_deg : float
    q_fixed : (6,) float
        The other joint angles [rad].
    is_excluded : (n2, n3) bool or None
        Poses never recommended: within :data:`LIMIT_MARGIN` of a joint limit or near a
        kinematic singularity (:data:`~flexarm.assembly.maps.SINGULAR_CONDITION`).
    """

    q2: FloatArray
    q3: FloatArray
    kcb: FloatArray
    normal_deg: FloatArray
    k_weak: FloatArray
    dir_deg: float
    q_fixed: FloatArray
    is_excluded: np.ndarray | None = None

    def best(self, n: int = 3) -> list[tuple[float, float, float]]:
        """The ``n`` poses with the largest limit: ``(q2 [deg], q3 [deg], K_c b [N/m])``,
        leaving out :attr:`is_excluded` poses (joint limits, singularities)."""
        bad = np.isnan(self.kcb)
        if self.is_excluded is not None:
            bad = bad | self.is_excluded
        flat = np.where(bad, -np.inf, self.kcb).ravel()
        idx = np.argsort(-flat, kind="stable")[:min(n, int((flat > -np.inf).sum()))]
        i2, i3 = np.unravel_index(idx, self.kcb.shape)
        return [(float(np.degrees(self.q2[a])), float(np.degrees(self.q3[b])),
                 float(self.kcb[a, b])) for a, b in zip(i2, i3, strict=True)]

    def text(self, n_best: int = 3) -> str:
        """The ``n_best`` best poses and the :func:`recommendation`, as ``chatter-map``
        prints them (deg, N/m)."""
        lines = [f"best: q2={b2:7.1f} deg q3={b3:7.1f} deg limit K_c b={k:.3g} N/m"
                 for b2, b3, k in self.best(n_best)]
        return "\n".join(lines + [recommendation(self)])

    def write_csv(self, path) -> Path:
        """One row per grid pose: ``q2_deg, q3_deg, kcb_limit_N_per_m, normal_deg,
        k_weak_N_per_m, excluded`` (``inf``: no limit, ``nan``: out of the joint limits;
        ``excluded`` 1: never recommended), written atomically."""
        G2, G3 = np.meshgrid(np.degrees(self.q2), np.degrees(self.q3), indexing="ij")
        ex = np.zeros(G2.shape) if self.is_excluded is None else self.is_excluded
        rows = np.column_stack([G2.ravel(), G3.ravel(), self.kcb.ravel(),
                                self.normal_deg.ravel(), self.k_weak.ravel(),
                                np.asarray(ex, float).ravel()])
        with atomic_path(path) as tmp:
            np.savetxt(tmp, rows, delimiter=",", comments="", fmt="%.9g",
                       header="q2_deg,q3_deg,kcb_limit_N_per_m,normal_deg,k_weak_N_per_m,"
                              "excluded")
        return Path(path)


def chatter_map(arm: ArmModel, q_fixed: ArrayLike, q2: ArrayLike, q3: ArrayLike,
                dir_deg: float, normal_deg: float | None = None,
                axes: ArrayLike | None = None, lower: ArrayLike | None = None,
                upper: ArrayLike | None = None) -> ChatterMap:
    """Limit ``K_c b`` at every (q2, q3) with joints 1, 4, 5, 6 from ``q_fixed``.

    ``normal_deg`` None: the worst surface orientation in the plane (:func:`worst_normal`).
    ``axes`` (2, 3): a fixed machining plane in the base frame; None: the plane normal
    to the tool axis at each pose.  The 2-DOF structures come from
    :func:`~flexarm.studies.contact.chatter.plane_model`, computed for all poses at once
    (:func:`~flexarm.studies.contact.plane_batch.plane_matrices`: one batched assembly
    and eigen-solve), and so are the stability limits.
    """
    q2 = np.asarray(q2, dtype=float)
    q3 = np.asarray(q3, dtype=float)
    base = np.asarray(q_fixed, dtype=float)
    G2, G3 = np.meshgrid(q2, q3, indexing="ij")
    Q = np.broadcast_to(base, G2.shape + (6,)).copy()
    Q[..., 1], Q[..., 2] = G2, G3
    ok = np.ones(G2.shape, dtype=bool)
    if lower is not None:
        ok &= np.all(Q >= np.asarray(lower), axis=-1)
    if upper is not None:
        ok &= np.all(Q <= np.asarray(upper), axis=-1)
    log.info("chatter map: %d poses", G2.size)
    MCK = np.tile(np.eye(2), G2.shape + (3, 1, 1))
    kw = np.full(G2.shape, np.nan)
    if ok.any():
        M, C, K, _ = plane_matrices(arm, Q[ok], axes)
        MCK[ok] = np.stack([M, C, K], axis=1)
        kw[ok] = np.linalg.eigvalsh(K)[:, 0]
    M, C, K = MCK[..., 0, :, :], MCK[..., 1, :, :], MCK[..., 2, :, :]
    if normal_deg is None:
        kc, nd = worst_normal(M, C, K, dir_deg)
    else:
        n, f = process_vectors(normal_deg, dir_deg)
        kc, nd = critical_kcb(M, C, K, n, f), np.full(G2.shape, float(normal_deg))
    kc = np.where(ok, kc, np.nan)
    log.info("chatter map done")
    return ChatterMap(q2, q3, kc, nd, kw, float(dir_deg), base,
                      _excluded(arm, Q, lower, upper))


def _excluded(arm: ArmModel, Q: FloatArray, lower, upper) -> np.ndarray:
    """(n2, n3) bool: poses within :data:`LIMIT_MARGIN` of a limit of joints 2 or 3, or
    near a kinematic singularity."""
    from ...assembly.maps import SINGULAR_CONDITION, jacobian_condition

    near = ~(jacobian_condition(arm, Q) <= SINGULAR_CONDITION)
    for bound, sign in ((lower, 1.0), (upper, -1.0)):
        if bound is not None:
            gap = sign * (Q[..., 1:3] - np.asarray(bound, dtype=float)[1:3])
            near |= np.any(gap < LIMIT_MARGIN, axis=-1)
    return near


def chatter_limits_map(arm: ArmModel, q_fixed: ArrayLike, lower: ArrayLike, upper: ArrayLike,
                       n: int = 25, dir_deg: float = 30.0, normal_deg: float | None = None,
                       axes: ArrayLike | None = None) -> ChatterMap:
    """:func:`chatter_map` on an ``n`` x ``n`` grid spanning the limits ``lower``, ``upper``
    (6,) [rad] of joints 2 and 3.

    Examples
    --------
    >>> from flexarm.assembly import emodel
    >>> from flexarm.robot import load_robot
    >>> r = load_robot()
    >>> cm = chatter_limits_map(emodel(r), r.pose("P1"), r.lower, r.upper, n=3)
    >>> np.degrees(cm.q2).round(1).tolist(), np.degrees(cm.q3).round(1).tolist()  # limits
    ([-90.0, 30.0, 150.0], [-180.0, -52.5, 75.0])
    >>> print(cm.text().splitlines()[0])  # the grid's limits are never recommended
    best: q2=   30.0 deg q3=  -52.5 deg limit K_c b=1.8e+05 N/m
    """
    if n < 2:
        raise ValueError(f"a map needs at least 2 grid points per joint, got {n}")
    lo, hi = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
    return chatter_map(arm, q_fixed, np.linspace(lo[1], hi[1], n), np.linspace(lo[2], hi[2], n),
                       dir_deg, normal_deg, axes, lo, hi)


def recommendation(cm: ChatterMap) -> str:
    """One sentence: the safest pose, its margin over the worst, and the thesis's advice."""
    if not cm.best(1):
        return ("No pose to recommend: every grid pose is out of reach, near a joint limit "
                "or near a kinematic singularity.")
    (b2, b3, bk), = cm.best(1)
    is_fin = np.isfinite(cm.kcb)
    finite = cm.kcb[is_fin]
    worst = float(finite.min()) if finite.size else np.nan
    corr = np.corrcoef(cm.k_weak[is_fin], finite)[0, 1] if finite.size > 2 else 0.0
    limit = ("no mode-coupling limit: stable for every K_c b" if np.isinf(bk) else
             f"limit K_c b = {bk:.3g} N/m, {bk / worst:.1f}x the worst pose's")
    n_ex = 0 if cm.is_excluded is None else int(cm.is_excluded.sum())
    excl = (f"; {n_ex} poses within {np.degrees(LIMIT_MARGIN):.0f} deg of a joint limit or "
            f"near a singularity not considered" if n_ex else "")
    return (f"Machine at q2 = {b2:.0f} deg, q3 = {b3:.0f} deg ({limit}; worst pose "
            f"{worst:.3g} N/m, {int((~is_fin & ~np.isnan(cm.kcb)).sum())} of {cm.kcb.size} "
            f"poses without a limit{excl}): choose stiff configurations "
            f"(limit vs weakest in-plane stiffness correlation {corr:+.2f}) and avoid feeding "
            "or loading along the weak Y (joint-1 tangential) direction.")
