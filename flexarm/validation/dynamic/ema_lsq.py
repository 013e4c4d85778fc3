"""Weighted least squares of modal identification: LSCF poles, LSFD residues, and the
poles refined on the modal model.

**LSCF** (least-squares complex frequency domain, common-denominator form; Verboven
2002, *Frequency-domain system identification for modal analysis*, ch. 5): every FRF of
a band is fitted by ``B_o(z) / A(z)`` with one denominator ``A`` shared by all of them,
polynomials in ``z = exp(i theta)``.  A band from near 0 Hz is mapped as ``theta = pi f /
f_hi`` with real coefficients (conjugate pole pairs; order ``j`` has ``2 j`` of them); a
band higher up (bottom above ``tol.ema_zoom_above`` of its top) is mapped onto the arc
``theta in [0, 2 pi ZOOM]`` with complex coefficients ("FRF zoom": each mode in the band
is one root, and close modes high up are resolved as well as low ones).  Each FRF is
first divided by its weighted RMS over the band (:func:`_frf_rms`).  The linearised
error ``sqrt(w_ok) (B_o - H_ok A)`` of FRF ``o`` at line ``k`` is minimised in least
squares with the textbook constraint (the constant term of ``A`` is 1: noise poles come
out unstable); the normal matrices are Toeplitz in the power index, so they are sums
over the lines of ``w exp(i theta m)`` (one matrix product), and the numerators are
eliminated per FRF (``D = sum_o T_o - S_o^H R_o^-1 S_o``).  The solution at each order
gives the poles of the stabilisation diagram.

**LSFD** (least-squares frequency domain): with the poles ``lambda_r`` fixed, each
receptance is linear in its residues: ``H_o = sum_r A_or / (i w - lambda_r) +
conj(A_or) / (i w - conj(lambda_r)) - L_o / w^2 + U_o`` (lower and upper residual
terms of the modes outside the band), solved per FRF with its line weights.

**Refinement**: the poles are then moved to the minimum of that LSFD residual itself
(:func:`refine_poles`), which removes most of the bias noise gives LSCF's linearised
estimate (damping ratios chiefly).

The weights ``w_ok`` are relative inverse variances of the lines, e.g.
:func:`~.frf_weights.coherence_weight` of an analyzer's coherence; uniform weights
give the textbook estimators.
"""

from __future__ import annotations

import logging

import numpy as np

from ...fe.typing import ArrayLike, FloatArray

__all__ = ["ZOOM", "lscf_poles", "lsfd_residues", "refine_poles", "pole_freq_damping"]

log = logging.getLogger(__name__)

#: Share of the unit circle the band is mapped onto; the rest keeps the band's two
#: ends apart (a pole just below it is not taken for one at its top) [-].
ZOOM = 0.9


def pole_freq_damping(poles: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Natural frequency [Hz] and damping ratio [-] of continuous-time poles
    ``s = -zeta omega + i omega sqrt(1 - zeta^2)`` [rad/s].

    Examples
    --------
    >>> f, z = pole_freq_damping([-0.02 * 2 * np.pi * 10 + 2j * np.pi * 10 * np.sqrt(1 - 4e-4)])
    >>> round(float(f[0]), 9), round(float(z[0]), 9)
    (10.0, 0.02)
    """
    s = np.atleast_1d(np.asarray(poles, complex))
    omega = np.abs(s)
    return omega / (2 * np.pi), -s.real / np.where(omega > 0, omega, 1.0)


def _band_lines(freq_hz, H, weights, f_lo, f_hi):
    freq = np.asarray(freq_hz, float)
    on = (freq >= f_lo) & (freq <= f_hi) & (freq > 0)
    H = np.asarray(H)[:, on]
    W = np.ones(H.shape) if weights is None else np.asarray(weights, float)[:, on]
    return freq[on], H, W


def _frf_rms(H: np.ndarray, W: np.ndarray) -> np.ndarray:
    """(n,) weighted RMS of each FRF over its lines (1 for an FRF that is all zero).

    Both least-squares steps that pool the FRFs (the common denominator, the pole
    refinement) see each FRF divided by it: a channel that moves little (a point near a
    node of the strong modes) is often where a weak mode shows best, and unscaled it
    would add nothing to the pooled fit.
    """
    rms = np.sqrt(np.sum(W * np.abs(H) ** 2, axis=1)
                  / np.maximum(np.sum(W, axis=1), np.finfo(float).tiny))
    return np.where(rms > 0, rms, 1.0)


def lscf_poles(freq_hz: ArrayLike, H: ArrayLike, f_lo: float, f_hi: float, max_order: int,
               weights: ArrayLike | None = None, real: bool | None = None
               ) -> list[np.ndarray]:
    """Poles of the common-denominator LSCF fit at orders ``1 ... max_order``.

    Parameters
    ----------
    freq_hz : (nf,) float
        Frequency lines [Hz].
    H : (n, nf) complex
        FRFs (any consistent unit; receptance in flexarm).
    f_lo, f_hi : float
        Band of the fit [Hz]; only its lines count.
    max_order : int
        Highest order: modes the denominator can hold (``max_order`` complex poles,
        or ``max_order`` conjugate pairs of real coefficients).
    weights : (n, nf) float, optional
        Relative weight of each line of each FRF [-] (default: all 1).
    real : bool, optional
        Real coefficients on ``0 ... f_hi`` (a band from near 0 Hz) or complex ones on
        the zoomed band; default: real when ``f_lo`` is below ``tol.ema_zoom_above``
        of ``f_hi`` (see the module docstring).

    Returns
    -------
    list of (j,) complex
        Continuous-time poles [rad/s] at order ``j = 1 ... max_order`` (every root,
        in the band or not; in the upper half-plane with real coefficients).

    Examples
    --------
    >>> f = np.linspace(5.0, 50.0, 400)
    >>> w, wr = 2 * np.pi * f, 2 * np.pi * 20.0
    >>> H = 1 / (wr**2 - w**2 + 2j * 0.02 * wr * w)
    >>> for real in (True, False):
    ...     fr, z = pole_freq_damping(lscf_poles(f, H[None], 5.0, 50.0, 10, real=real)[-1])
    ...     k = np.argmin(abs(fr - 20))
    ...     print(round(float(fr[k]), 6), round(float(z[k]), 6))
    20.0 0.02
    20.0 0.02
    """
    freq, Hb, W = _band_lines(freq_hz, H, weights, f_lo, f_hi)
    from ..tolerances import tol

    real = f_lo <= tol.ema_zoom_above * f_hi if real is None else bool(real)
    # an order needs as many lines as coefficients
    n = min(int(max_order) * (2 if real else 1), len(freq) - 1)
    W = W / (np.max(W) or 1.0)
    Hb = Hb / _frf_rms(Hb, W)[:, None]
    # theta = ts (omega - omega_0) [rad]: 0 ... pi over 0 ... f_hi, or the zoom
    ts, f0 = (0.5 / f_hi, 0.0) if real else (ZOOM / (f_hi - f_lo), f_lo)
    m = np.arange(-n, n + 1)
    E = np.exp(1j * np.outer(2 * np.pi * ts * (freq - f0), m))  # (nf, 2n+1)
    r = W @ E  # (n_frf, 2n+1): R_o[j, l] = r_o(l - j)
    s = -(W * Hb) @ E
    t = np.sum(W * np.abs(Hb) ** 2, axis=0) @ E
    if real:
        r, s, t = r.real, s.real, t.real
    idx = np.arange(n + 1)[None, :] - np.arange(n + 1)[:, None] + n  # l - j + n
    R, S, T = r[:, idx], s[:, idx], t[idx]
    gap = np.pi * (1 - ZOOM)
    out = []
    for j in range(2 if real else 1, n + 1, 2 if real else 1):
        sl = slice(0, j + 1)
        X = np.linalg.solve(R[:, sl, sl], S[:, sl, sl])
        D = T[sl, sl] - np.einsum("oji,ojl->il", S[:, sl, sl].conj(), X)
        # constant term 1 (the highest power of z^-1 in the textbook's basis): noise
        # poles then come out unstable and leave the diagram, physical ones stay
        a = np.linalg.lstsq(D[1:, 1:], -D[1:, 0], rcond=None)[0]
        z = np.roots(np.r_[1.0, a][::-1])
        if real:  # conjugate pairs: the upper one of each
            z = z[z.imag > 0]
            ang = np.angle(z)
        else:  # angles from just below the band's bottom round to past its top
            z = z[np.abs(z) > 0]
            ang = np.mod(np.angle(z) + gap, 2 * np.pi) - gap
        out.append((np.log(np.abs(z)) + 1j * ang) / ts + 2j * np.pi * f0)
    log.debug("LSCF %g-%g Hz (%s): %d FRFs, %d lines, orders 1-%d", f_lo, f_hi,
              "real" if real else "zoomed", len(Hb), len(freq), len(out))
    return out


def _basis(freq: np.ndarray, poles: np.ndarray) -> np.ndarray:
    """(nf, 2k+4) complex columns of the LSFD model per real unknown."""
    iw = 2j * np.pi * freq[:, None]
    a, b = 1 / (iw - poles), 1 / (iw - poles.conj())
    lower = -1 / (2 * np.pi * freq[:, None]) ** 2
    one = np.ones((len(freq), 1))
    return np.hstack([a + b, 1j * (a - b), lower, 1j * lower, one, 1j * one])


def lsfd_residues(freq_hz: ArrayLike, H: ArrayLike, poles: ArrayLike, f_lo: float,
                  f_hi: float, weights: ArrayLike | None = None
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Residues of fixed poles in every FRF (weighted LSFD, with residual terms).

    Parameters
    ----------
    freq_hz : (nf,) float
        Frequency lines [Hz].
    H : (n, nf) complex
        Receptances [m/N].
    poles : (k,) complex
        Poles [rad/s] (upper half-plane).
    f_lo, f_hi : float
        Band of the fit [Hz].
    weights : (n, nf) float, optional
        Relative weight of each line of each FRF [-] (default: all 1).

    Returns
    -------
    A : (n, k) complex
        Residues [m/(N s)] of ``A / (i w - lambda) + conj(A) / (i w - conj(lambda))``.
    synthesised : (n, nf) complex
        The fitted model at every line [m/N] (NaN outside the band).

    Examples
    --------
    >>> f = np.linspace(5.0, 50.0, 200)
    >>> lam = np.array([-0.02 * 2 * np.pi * 20 + 2j * np.pi * 20 * np.sqrt(1 - 4e-4)])
    >>> iw = 2j * np.pi * f
    >>> H = (3 - 1j) / (iw - lam) + (3 + 1j) / (iw - lam.conj())
    >>> A, _ = lsfd_residues(f, H[None], lam, 5.0, 50.0)
    >>> np.round(A, 9).tolist()
    [[(3-1j)]]
    """
    freq_all = np.asarray(freq_hz, float)
    H = np.asarray(H, complex)
    poles = np.asarray(poles, complex)
    on = (freq_all >= f_lo) & (freq_all <= f_hi) & (freq_all > 0)
    freq, Hb, W = _band_lines(freq_all, H, weights, f_lo, f_hi)
    P, C, _ = _lsfd(freq, Hb, W, poles)
    k = len(poles)
    synth = np.full(H.shape, np.nan + 0j)
    synth[:, on] = (P @ C).T
    return (C[:k] + 1j * C[k:2 * k]).T, synth


def _lsfd(freq: np.ndarray, H: np.ndarray, W: np.ndarray, poles: np.ndarray,
          frf_scale: np.ndarray | None = None):
    """(basis (nf, 2k+4), coefficients (2k+4, n), weighted residual vector) of the LSFD
    fit of ``H`` (n, nf) on the lines ``freq`` with line weights ``W``; each FRF's
    residual times ``frf_scale`` (n,) (a constant factor per FRF leaves its own fit
    unchanged, so the FRFs that share their line weights still share one solve)."""
    P = _basis(freq, poles)
    Pr = np.vstack([P.real, P.imag])  # (2nf, 2k+4)
    norm = np.linalg.norm(Pr, axis=0)
    norm[norm == 0] = 1.0
    Y = np.vstack([H.real.T, H.imag.T])  # (2nf, n)
    sw = np.sqrt(np.vstack([W.T, W.T]))
    if np.all(sw == sw[:, :1]):  # one set of weights: one solve for every FRF
        C = np.linalg.lstsq(Pr * (sw[:, :1] / norm), Y * sw[:, :1], rcond=None)[0]
    else:
        C = np.column_stack([np.linalg.lstsq(Pr * (sw[:, [o]] / norm), Y[:, o] * sw[:, o],
                                             rcond=None)[0] for o in range(Y.shape[1])])
    C = C / norm[:, None]  # (2k+4, n)
    res = (Pr @ C - Y) * sw
    return P, C, (res if frf_scale is None else res * frf_scale).ravel()


def refine_poles(freq_hz: ArrayLike, H: ArrayLike, poles: ArrayLike, f_lo: float,
                 f_hi: float, weights: ArrayLike | None = None) -> np.ndarray:
    """Poles moved to the least-squares optimum of the modal model itself.

    LSCF's poles minimise a linearised error (``B - H A``), which noise biases, chiefly
    in damping.  Each pole is moved, the others held, to minimise the weighted LSFD
    residual of the lines around it (each FRF scaled to unit RMS over the band, as in
    :func:`lscf_poles`; ``tol.ema_refine_window`` times ``zeta f`` each side, at least
    ``tol.ema_refine_lines`` lines; the residues of the pole and its neighbours solved
    anew at every step, variable projection; the modes farther away taken off with their
    residues from the whole band), one pole after the other up the band.  A move is kept
    only when it lowers that residual, stays within ``tol.ema_refine_step`` in frequency
    and keeps a damping ratio between 0 and 0.2.

    Parameters
    ----------
    freq_hz : (nf,) float
        Frequency lines [Hz].
    H : (n, nf) complex
        Receptances [m/N].
    poles : (k,) complex
        Poles [rad/s] (upper half-plane), e.g. from :func:`lscf_poles`.
    f_lo, f_hi : float
        Band of the fit [Hz].
    weights : (n, nf) float, optional
        Relative weight of each line of each FRF [-] (default: all 1).

    Returns
    -------
    (k,) complex
        The refined poles [rad/s].

    Examples
    --------
    >>> f = np.linspace(5.0, 50.0, 400)
    >>> true = -0.02 * 2 * np.pi * 20 + 2j * np.pi * 20 * np.sqrt(1 - 4e-4)
    >>> iw = 2j * np.pi * f
    >>> H = (-1j / (iw - true) + 1j / (iw - np.conj(true)))[None]  # a real mode
    >>> fr, z = pole_freq_damping(refine_poles(f, H, [true * 1.003 + 0.5], 5.0, 50.0))
    >>> round(float(fr[0]), 6), round(float(z[0]), 6)
    (20.0, 0.02)
    """
    from scipy.optimize import least_squares

    from ..tolerances import tol

    freq_all = np.asarray(freq_hz, float)
    H = np.asarray(H, complex)
    W_all = np.ones(H.shape) if weights is None else np.asarray(weights, float)
    _, Hb, Wb = _band_lines(freq_all, H, W_all, f_lo, f_hi)
    frf_scale = 1.0 / _frf_rms(Hb, Wb)
    poles = np.array(poles, complex)
    df = float(np.median(np.diff(freq_all))) if len(freq_all) > 1 else 1.0
    A = lsfd_residues(freq_all, H, poles, f_lo, f_hi, weights)[0]  # (n, k)
    for r in np.argsort(pole_freq_damping(poles)[0]):
        fr, zr = pole_freq_damping(poles[r])
        half = max(tol.ema_refine_window * zr[0] * fr[0], 0.5 * tol.ema_refine_lines * df)
        on = (freq_all >= max(f_lo, fr[0] - half)) & (freq_all <= min(f_hi, fr[0] + half)) \
            & (freq_all > 0)
        if on.sum() < tol.ema_refine_lines // 2:
            continue
        is_near = np.abs(pole_freq_damping(poles)[0] - fr[0]) < 3 * half
        is_near[r] = False
        # the far modes' tails, from the residues of the whole band, taken off
        far = ~is_near
        far[r] = False
        iw = 2j * np.pi * freq_all[on][:, None]
        tails = (A[:, far] @ (1 / (iw - poles[far])).T
                 + A[:, far].conj() @ (1 / (iw - poles[far].conj())).T)
        Hr = H[:, on] - tails
        near = poles[is_near]
        scale = abs(poles[r])

        def residual(x, on=on, Hr=Hr, near=near, scale=scale):
            return _lsfd(freq_all[on], Hr, W_all[:, on],
                         np.r_[scale * (x[0] + 1j * x[1]), near], frf_scale)[2]

        x0 = np.array([poles[r].real, poles[r].imag]) / scale
        start = residual(x0)
        sol = least_squares(residual, x0, method="lm", max_nfev=60, xtol=1e-12, ftol=1e-12,
                            x_scale=np.array([max(abs(x0[0]), 1e-6), 1e-3]))
        new = scale * (sol.x[0] + 1j * sol.x[1])
        fn, zn = pole_freq_damping(new)
        if (2 * sol.cost < start @ start and 0 < zn[0] < 0.2
                and abs(fn[0] / fr[0] - 1) < tol.ema_refine_step):
            poles[r] = new
    return poles
