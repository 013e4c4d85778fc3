"""Modal parameters from measured FRFs: LSCF poles, LSFD residues (sdypy-ema).

The least-squares complex-frequency (LSCF, "PolyMAX"-family) estimator of sdypy-ema
fits a common-denominator model to every FRF of a pose at model orders 2, 4, ...,
``2 max_order``; its poles at successive orders give the stabilisation diagram.  The
poles kept are picked automatically, as an analyst picks columns of the diagram: a
pole is *stable* when the previous order has one within ``STABLE_FREQ`` in frequency
and ``STABLE_DAMPING`` in damping ratio; stable poles within ``CLUSTER`` of each other
form a column, and a column stable at ``min_stable`` of the orders is a mode (its pole
at the highest order is taken).  LSFD (sdypy-ema) then fits the residues of those
poles to every FRF, with lower and upper residual terms.  With several references,
the residues of a mode form a rank-one matrix ``phi_out phi_ref^T``: its dominant
left singular vector is the mode shape, turned real (normal-mode approximation) by
the rotation that maximises its real part.

Modal mass: sdypy-ema's residues ``A`` are those of ``H = sum_r A_r / (i w - l_r) +
conj``, so a mass-normalised real shape ``psi`` has ``psi psi^T = 2 i w_d A_r``.  At the
driving points (an output that is also a reference) this gives ``psi_d^2``, and the unit
shape ``u`` has the modal mass ``m = u_d^2 / psi_d^2`` (least squares over the driving
points; 0, not known, without one): ``H = sum_r u u^T / (m_r (w_r^2 - w^2 + 2 i zeta_r
w_r w))``.

Why a library: LSCF/LSFD is standard and sdypy-ema is its maintained open
implementation (from pyEMA/OpenModal); only the automatic pole picking (a GUI in
sdypy-ema) is ours.
"""

from __future__ import annotations

import contextlib
import io
import logging
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...fe.errors import MissingDependencyError
from ...fe.typing import PathType
from ..data.formats.uff import UffFrf, UffOptions, read_uff
from ..data.shape_data import ShapeData

__all__ = ["STABLE_FREQ", "STABLE_DAMPING", "CLUSTER", "PoseModes", "EmaResult",
           "identify_modes", "run_ema", "stable_poles"]

log = logging.getLogger(__name__)

#: A pole is stable when the previous order has one this close in frequency [-] ...
STABLE_FREQ = 0.01
#: ... and in damping ratio [-] (relative).
STABLE_DAMPING = 0.05
#: Stable poles closer than this (relative frequency gap) form one column [-].
CLUSTER = 0.005
_MAX_DAMPING = 0.2  # poles more damped than this are numerical


def _sdypy_model(H, freq, lower, upper, max_order):
    try:
        from sdypy import EMA
    except ImportError:
        raise MissingDependencyError("sdypy-ema", "modal parameters from FRFs") from None
    model = EMA.Model(frf=H, freq=freq, lower=lower, upper=upper, pol_order_high=max_order,
                      frf_form="receptance")
    with contextlib.redirect_stderr(io.StringIO()):  # its progress bars
        model.get_poles(method="lscf", show_progress=False)
    return model


def stable_poles(pole_freq, pole_xi, f_lo: float, f_hi: float) -> np.ndarray:
    """(k, 4) rows ``(order index, pole index, freq [Hz], damping ratio)`` of the stable
    poles of an LSCF run (``pole_freq``, ``pole_xi``: one array per order).

    Examples
    --------
    >>> f = [np.array([10.0]), np.array([10.02, 30.0]), np.array([10.01, 31.0])]
    >>> z = [np.array([0.02]), np.array([0.0201, 0.05]), np.array([0.0202, 0.05])]
    >>> stable_poles(f, z, 1.0, 100.0)[:, :2].astype(int).tolist()
    [[1, 0], [2, 0]]
    """
    rows = []
    for j in range(1, len(pole_freq)):
        fp, xp = np.asarray(pole_freq[j]), np.asarray(pole_xi[j])
        fq, xq = np.asarray(pole_freq[j - 1]), np.asarray(pole_xi[j - 1])
        ok = (xp > 0) & (xp < _MAX_DAMPING) & (fp >= f_lo) & (fp <= f_hi)
        if not fq.size or not ok.any():
            continue
        near = (np.abs(fq[None, :] - fp[:, None]) < STABLE_FREQ * fp[:, None]) & \
            (np.abs(xq[None, :] - xp[:, None]) < STABLE_DAMPING * xp[:, None])
        k = np.flatnonzero(ok & near.any(axis=1))
        rows.append(np.column_stack([np.full(len(k), j), k, fp[k], xp[k]]))
    return np.concatenate(rows) if rows else np.zeros((0, 4))


def _columns(stable: np.ndarray, n_orders: int, min_stable: float) -> np.ndarray:
    """One pole per column of the diagram that is stable often enough."""
    if not len(stable):
        return np.zeros((0, 4))
    s = stable[np.argsort(stable[:, 2], kind="stable")]
    cols = np.split(s, np.flatnonzero(np.diff(s[:, 2]) / s[:-1, 2] > CLUSTER) + 1)
    keep = [c[np.argmax(c[:, 0])] for c in cols
            if len(np.unique(c[:, 0])) >= min_stable * n_orders]
    return np.array(keep) if keep else np.zeros((0, 4))


def _real_shape(u: np.ndarray) -> np.ndarray:
    """Real normal-mode approximation of a complex shape, largest entry positive."""
    u = u * np.exp(-0.5j * np.angle(np.sum(u**2)))
    r = u.real
    return r * np.sign(r[np.argmax(np.abs(r))])


@dataclass(frozen=True, eq=False)
class PoseModes:
    """Modes identified from the FRFs of one pose.

    Attributes
    ----------
    frf : UffFrf
        The measured FRFs used.
    freq_hz, damping : (k,) float
        Natural frequencies [Hz] and damping ratios [-].
    nodes, dirs : (m,) int, str
        Output DOFs of the shapes.
    shapes : (k, m) float
        Real mode shapes (unit norm, largest entry positive).
    synthesised : (n, nf) complex
        FRFs of the identified modal model (with residual terms) [m/N]; NaN
        outside the fitted band.
    stable : (s, 4) float
        Stable poles: order index, pole index, frequency [Hz], damping ratio.
    all_poles : list of (2, p) float
        Frequency [Hz] and damping ratio of every pole per order (the diagram).
    modal_mass : (k,) float
        Modal mass of each unit shape (SI; 0 without a driving point).
    """

    frf: UffFrf
    freq_hz: np.ndarray
    damping: np.ndarray
    nodes: np.ndarray
    dirs: np.ndarray
    shapes: np.ndarray
    synthesised: np.ndarray
    stable: np.ndarray
    all_poles: list
    modal_mass: np.ndarray | None = None


#: Fewest frequency lines in the band that an identification is tried on.
MIN_LINES = 20


def _band(frf: UffFrf, f_lo, f_hi):
    freq = frf.freq_hz
    lo = float(freq[0] if f_lo is None else f_lo)
    hi = float(freq[-1] if f_hi is None else min(f_hi, freq[-1]))
    if not freq[0] <= lo < hi:
        raise ValueError(f"pose '{frf.pose}': the band {lo:g}-{hi:g} Hz is not inside the "
                         f"measured lines {freq[0]:g}-{freq[-1]:g} Hz")
    return lo, hi


def _modal_masses(R: np.ndarray, shapes: np.ndarray, dofs: list, refs: list,
                  omega_d: np.ndarray) -> np.ndarray:
    """(k,) modal mass of unit ``shapes`` (k, m) from residues ``R`` (k, m, n_ref) at the
    driving points (see the module docstring)."""
    pairs = [(dofs.index(r), k) for k, r in enumerate(refs) if r in dofs]
    if not pairs:
        return np.zeros(len(shapes))
    o, i = np.array(pairs).T
    psi2 = (2j * omega_d[:, None] * R[:, o, i]).real  # psi_d^2 per mode and driving point
    u2 = shapes[:, o] ** 2
    inv = np.sum(u2 * psi2, axis=1) / np.maximum(np.sum(u2**2, axis=1), np.finfo(float).tiny)
    return np.where(inv > 0, 1.0 / np.where(inv > 0, inv, 1.0), 0.0)


def identify_modes(frf: UffFrf, f_lo: float | None = None, f_hi: float | None = None,
                   max_order: int = 40, min_stable: float = 0.25) -> PoseModes:
    """LSCF poles and LSFD shapes from the FRFs of one pose.

    Parameters
    ----------
    frf : UffFrf
        Receptances of one pose, every output per every reference (at least one FRF
        per reference that sees each mode).
    f_lo, f_hi : float, optional
        Band of the fit [Hz] (default: the measured lines).
    max_order : int
        Highest LSCF order (model orders 2 ... ``2 max_order``).
    min_stable : float
        Share of the orders at which a column must be stable to be a mode [-].
    """
    lo, hi = _band(frf, f_lo, f_hi)
    n_lines = int(np.sum((frf.freq_hz >= lo) & (frf.freq_hz <= hi)))
    if n_lines < MIN_LINES:
        raise ValueError(f"pose '{frf.pose}': {n_lines} frequency lines between {lo:g} and "
                         f"{hi:g} Hz are too few to identify modes (LSCF needs {MIN_LINES}): "
                         f"measure or export the FRFs with more lines")
    live = np.abs(frf.H).max(axis=1) > 0  # DOFs that never move carry no information
    H, freq = frf.H[live], frf.freq_hz
    model = _sdypy_model(H, freq, lo, hi, int(max_order))
    stable = stable_poles(model.pole_freq, model.pole_xi, lo, hi)
    picked = _columns(stable, len(model.pole_freq), min_stable)
    if not len(picked):
        raise ValueError(f"pose '{frf.pose}': no stable pole between {lo:g} and {hi:g} Hz "
                         f"up to order {2 * max_order}: give a wider --band or a higher "
                         f"--max-order, or measure more lines")
    model.pole_ind = picked[:, :2].astype(int)
    model.nat_freq, model.nat_xi = picked[:, 2], picked[:, 3]
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # band edge clamped to a line
        Hs, A = model.get_constants(method="lsfd", f_lower=lo, f_upper=hi)
    outs = [f"{n}{d}" for n, d in zip(frf.out_nodes[live], frf.out_dirs[live], strict=True)]
    dofs = list(dict.fromkeys(outs))
    refs = list(dict.fromkeys(f"{n}{d}" for n, d in zip(frf.in_nodes[live], frf.in_dirs[live],
                                                        strict=True)))
    ins = [f"{n}{d}" for n, d in zip(frf.in_nodes[live], frf.in_dirs[live], strict=True)]
    R = np.zeros((len(picked), len(dofs), len(refs)), complex)
    R[:, [dofs.index(o) for o in outs], [refs.index(i) for i in ins]] = A.T
    U = np.linalg.svd(R)[0][:, :, 0]  # dominant left singular vector per mode
    shapes = np.array([_real_shape(u) for u in U])
    mass = _modal_masses(R, shapes, dofs, refs,
                         2 * np.pi * picked[:, 2] * np.sqrt(1 - picked[:, 3] ** 2))
    first = [outs.index(d) for d in dofs]
    # sdypy-ema pads lines from 0 Hz and cuts at the band's top: align by frequency
    synth = np.full(frf.H.shape, np.nan + 0j)
    col = np.searchsorted(freq, model.freq)
    on = (col < len(freq)) & np.isclose(freq[np.minimum(col, len(freq) - 1)], model.freq)
    on &= (model.freq >= lo) & (model.freq <= hi)
    rows = np.flatnonzero(live)
    synth[np.ix_(rows, col[on])] = Hs[:, on]
    synth[~live] = 0.0
    log.info("ema pose %s: %d modes from %d FRFs", frf.pose, len(picked), int(live.sum()))
    return PoseModes(frf, picked[:, 2], picked[:, 3], frf.out_nodes[live][first],
                     frf.out_dirs[live][first], shapes, synth, stable,
                     [np.array([f, x]) for f, x in zip(model.pole_freq, model.pole_xi,
                                                       strict=True)], mass)


@dataclass(frozen=True, eq=False)
class EmaResult:
    """Modes identified at every pose of a universal file (:func:`run_ema`), with the
    file's test geometry (:class:`~flexarm.validation.data.formats.uff_geometry.PoseGeometry`
    per pose) when it has one."""

    poses: tuple
    geometry: tuple = ()

    def write(self, path: PathType, comments=()) -> Path:
        """:meth:`modal` as a measurement file; a universal file (``.uff``, ``.unv``) also
        gets the geometry and each shape's modal mass (:func:`~.uff_write.write_uff`)."""
        from ..data.formats import registry
        from ..data.formats.uff import EXTENSIONS
        from ..data.formats.uff_write import write_uff

        if Path(path).suffix.lower() not in EXTENSIONS:
            return Path(registry.write(path, self.modal(), comments=comments))
        mass = np.concatenate([np.zeros(len(pm.freq_hz)) if pm.modal_mass is None
                               else pm.modal_mass for pm in self.poses])
        return write_uff(path, self.modal(), geometry=self.geometry, modal_mass=mass,
                         description=" ".join(map(str, comments)) or "flexarm ema")

    def modal(self) -> ShapeData:
        """Frequencies, damping and shapes as measured modal data, on one DOF set for
        every pose: the union of the poses' channels, a channel that did not move at one
        pose (exactly zero there, e.g. by the geometry of that pose) holding zeros in its
        modes."""
        keys = list(dict.fromkeys(f"{n} {d}" for pm in self.poses
                                  for n, d in zip(pm.nodes, pm.dirs, strict=True)))
        nodes = np.array([int(k.split()[0]) for k in keys], np.int64)
        dirs = np.array([k.split()[1] for k in keys])
        shapes = []
        for pm in self.poses:
            S = np.zeros((len(pm.freq_hz), len(keys)), dtype=pm.shapes.dtype)
            S[:, [keys.index(f"{n} {d}") for n, d in zip(pm.nodes, pm.dirs, strict=True)]] = \
                pm.shapes
            shapes.append(S)
        k = [len(pm.freq_hz) for pm in self.poses]
        return ShapeData(poses=np.repeat([pm.frf.pose for pm in self.poses], k),
                         q=np.concatenate([np.tile(pm.frf.q, (n, 1))
                                           for pm, n in zip(self.poses, k, strict=True)]),
                         modes=np.concatenate([np.arange(1, n + 1) for n in k]),
                         freq_hz=np.concatenate([pm.freq_hz for pm in self.poses]),
                         damping_ratio=np.concatenate([pm.damping for pm in self.poses]),
                         nodes=nodes, dirs=dirs, shapes=np.concatenate(shapes))

    def text(self) -> str:
        """Modes per pose (frequency, damping ratio) and the FRF fit's error."""
        from ...fe.text import text_table

        rows = []
        for pm in self.poses:
            ok = np.isfinite(pm.synthesised)  # NaN: lines outside the fitted band
            err = np.linalg.norm((pm.synthesised - pm.frf.H)[ok]) / np.linalg.norm(
                pm.frf.H[ok])
            for r, (f, z) in enumerate(zip(pm.freq_hz, pm.damping, strict=True)):
                rows.append([pm.frf.pose, r + 1, f, 100 * z, 100 * err if r == 0 else ""])
        return text_table(["pose", "mode", "freq_Hz", "zeta_%", "fit_err_%"], rows, "{:.3f}")

    def write_plots(self, stem) -> list:
        """``<stem>.stabilisation_<pose>.png`` and ``<stem>.frf_<pose>.png`` per pose."""
        from .ema_plots import plot_stabilisation, plot_synthesis

        out = []
        for pm in self.poses:
            out.append(plot_stabilisation(f"{stem}.stabilisation_{pm.frf.pose}.png", pm))
            out.append(plot_synthesis(f"{stem}.frf_{pm.frf.pose}.png", pm))
        return out


def run_ema(path: PathType | list, f_lo: float | None = None, f_hi: float | None = None,
            max_order: int = 40, min_stable: float = 0.25,
            uff: UffOptions | None = None) -> EmaResult:
    """Identify modes from the 58 FRFs of a universal file (or a list of
    :class:`UffFrf`), pose by pose (:func:`identify_modes`); ``uff`` says what the file
    does not (the pose it was measured at, what its ordinates are)."""
    geometry = ()
    if isinstance(path, list | tuple):
        frfs = list(path)
    else:
        uff = uff or UffOptions()
        label, q = uff.pose if uff.pose is not None else (None, None)
        content = read_uff(path, label, q, uff.response)
        frfs, geometry = list(content.frfs), content.geometry
    if not frfs:
        raise ValueError(f"{path}: no FRFs (58 datasets) to identify modes from")
    return EmaResult(tuple(identify_modes(f, f_lo, f_hi, max_order, min_stable)
                           for f in frfs), geometry)
