"""Modal parameters from measured FRFs: LSCF poles, LSFD residues, wide bands split.

The least-squares complex-frequency (LSCF, "PolyMAX"-family) estimator fits a
common-denominator model to every FRF of a pose at orders 1, 2, ..., ``max_order``
(:mod:`.ema_lsq`, with the band zoomed onto the unit circle); its poles at successive
orders give the stabilisation diagram.  The poles kept are picked automatically, as an
analyst picks columns of the diagram: a pole is *stable* when the previous order has
one within ``STABLE_FREQ`` in frequency and ``STABLE_DAMPING`` in damping ratio; stable
poles within ``CLUSTER`` of each other form a column (one pole per order: a group with
two poles at as many orders as make a mode is two close modes, cut at its widest gap),
and a column stable at ``min_stable`` of the orders is a mode (its medoid pole, the one
nearest the column's median frequency, is taken: a noise pole that joins a column at a
high order does not become the mode).  A wide band is split into overlapping sub-bands
of a few expected modes each and their poles merged, one per mode (:mod:`.ema_bands`).
Each pole is then refined on the modal model's own residual around it, and LSFD fits
the residues of the poles to every FRF over the whole band, with lower and upper
residual terms.  With several references, the residues of a mode form a rank-one
matrix ``phi_out phi_ref^T``: its dominant left singular vector is the mode shape,
turned real (normal-mode approximation) by the rotation that maximises its real part.

Lines are weighted in both least-squares steps by the inverse variance of an H1
estimate, ``gamma^2 / (1 - gamma^2)`` of their coherence
(:func:`~.frf_weights.coherence_weight`, floored at ``tol.ema_weight_floor`` of the
largest) when the file has one for every FRF, and equally otherwise; where the FRFs are
pooled (the common denominator, the pole refinement) each is scaled to unit RMS over the
band, so that the channels the strong modes barely move, where weak modes show, count.

Modal mass: the residues ``A`` are those of ``H = sum_r A_r / (i w - l_r) + conj``, so a
mass-normalised real shape ``psi`` has ``psi psi^T = 2 i w_d A_r``.  At the driving
points (an output that is also a reference) this gives ``psi_d^2``, and the unit shape
``u`` has the modal mass ``m = u_d^2 / psi_d^2`` (least squares over the driving points;
0, not known, without one): ``H = sum_r u u^T / (m_r (w_r^2 - w^2 + 2 i zeta_r w_r w))``.

Why our own estimator: sdypy-ema's LSCF (the maintained open implementation, from
pyEMA/OpenModal) weights every line alike and maps the band from 0 Hz, so it can take
neither an analyzer's coherence nor a narrow sub-band high up; the estimator is the
textbook common-denominator one (Verboven, *Frequency-domain system identification for
modal analysis*, PhD thesis, VUB 2002, ch. 5) and is checked against analytic modal sums
in the tests.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...fe.typing import PathType
from ..data.formats.uff import UffFrf, UffOptions, read_uff
from ..data.shape_data import ShapeData
from ..tolerances import tol
from .ema_bands import sub_bands
from .ema_lsq import lsfd_residues, pole_freq_damping, refine_poles
from .ema_poles import CLUSTER, STABLE_DAMPING, STABLE_FREQ, merged_poles, stable_poles
from .frf_weights import coherence_weight

__all__ = ["STABLE_FREQ", "STABLE_DAMPING", "CLUSTER", "PoseModes", "EmaResult",
           "identify_modes", "run_ema", "stable_poles", "line_weights"]

log = logging.getLogger(__name__)

def _real_shape(u: np.ndarray) -> np.ndarray:
    """Real normal-mode approximation of a complex shape, largest entry positive."""
    u = u * np.exp(-0.5j * np.angle(np.sum(u**2)))
    r = u.real
    return r * np.sign(r[np.argmax(np.abs(r))])


def line_weights(coherence) -> np.ndarray | None:
    """(n, nf) weight of each FRF line from its coherence ``gamma^2``: ``gamma^2 / (1 -
    gamma^2)``, at least ``tol.ema_weight_floor`` of the largest; None without one.

    Examples
    --------
    >>> line_weights(np.array([[0.5, 0.9, 0.0]])).round(6).tolist()
    [[1.0, 9.0, 9e-06]]
    """
    if coherence is None:
        return None
    W = coherence_weight(coherence)
    top = float(np.max(W)) if W.size else 0.0
    return np.maximum(W, tol.ema_weight_floor * top) if top > 0 else np.ones(W.shape)


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
        Stable poles of every sub-band: order index (order - 1), pole index, frequency
        [Hz], damping ratio.
    all_poles : list of (2, p) float
        Frequency [Hz] and damping ratio of every pole per order (the diagram), the
        sub-bands' poles side by side.
    modal_mass : (k,) float
        Modal mass of each unit shape (SI; 0 without a driving point).
    bands : tuple of SubBand
        The LSCF fits the band was split into (one: not split).
    weighted : bool
        Whether the lines were weighted by their coherence.
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
    bands: tuple = ()
    weighted: bool = False


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
                   max_order: int = 40, min_stable: float = 0.25, *,
                   split: str | int = "auto", weighted: bool = True) -> PoseModes:
    """LSCF poles and LSFD shapes from the FRFs of one pose.

    Parameters
    ----------
    frf : UffFrf
        Receptances of one pose, every output per every reference (at least one FRF
        per reference that sees each mode).
    f_lo, f_hi : float, optional
        Band of the fit [Hz] (default: the measured lines).
    max_order : int
        Highest LSCF order (modes the denominator of one fit can hold).
    min_stable : float
        Share of the orders at which a column must be stable to be a mode [-].
    split : "auto", "none" or int
        Sub-bands of a wide band (:func:`~.ema_bands.sub_bands`).
    weighted : bool
        Weight the lines by their coherence when the FRFs have one.

    Examples
    --------
    >>> f = np.arange(1.0, 200.0, 0.25)
    >>> w, wr = 2 * np.pi * f, 2 * np.pi * np.array([[40.0], [120.0]])
    >>> H = np.sum(1 / (wr**2 - w**2 + 0.02j * wr * w), axis=0)[None] * 1e6
    >>> one = np.array([1])
    >>> frf = UffFrf("P1", np.zeros(6), f, one, np.array(["z"]), one, np.array(["z"]), H)
    >>> pm = identify_modes(frf)
    >>> pm.freq_hz.round(4).tolist(), pm.damping.round(5).tolist()
    ([40.0, 120.0], [0.01, 0.01])
    """
    lo, hi = _band(frf, f_lo, f_hi)
    n_lines = int(np.sum((frf.freq_hz >= lo) & (frf.freq_hz <= hi)))
    if n_lines < MIN_LINES:
        raise ValueError(f"pose '{frf.pose}': {n_lines} frequency lines between {lo:g} and "
                         f"{hi:g} Hz are too few to identify modes (LSCF needs {MIN_LINES}): "
                         f"measure or export the FRFs with more lines")
    live = np.abs(frf.H).max(axis=1) > 0  # DOFs that never move carry no information
    H, freq = frf.H[live], frf.freq_hz
    W = line_weights(None if frf.coherence is None or not weighted else frf.coherence[live])
    bands = sub_bands(freq, H, lo, hi, int(max_order), split, W, MIN_LINES)
    poles, stable, diagram = merged_poles(freq, H, W, bands, min_stable)
    if not len(poles):
        raise ValueError(f"pose '{frf.pose}': no stable pole between {lo:g} and {hi:g} Hz "
                         f"up to order {max_order}: give a wider --band or a higher "
                         f"--max-order, or measure more lines")
    poles = refine_poles(freq, H, poles, lo, hi, W)
    poles = poles[np.argsort(pole_freq_damping(poles)[0])]
    fn, zeta = pole_freq_damping(poles)
    A, synth_live = lsfd_residues(freq, H, poles, lo, hi, W)
    outs = [f"{n}{d}" for n, d in zip(frf.out_nodes[live], frf.out_dirs[live], strict=True)]
    dofs = list(dict.fromkeys(outs))
    refs = list(dict.fromkeys(f"{n}{d}" for n, d in zip(frf.in_nodes[live], frf.in_dirs[live],
                                                        strict=True)))
    ins = [f"{n}{d}" for n, d in zip(frf.in_nodes[live], frf.in_dirs[live], strict=True)]
    R = np.zeros((len(poles), len(dofs), len(refs)), complex)
    R[:, [dofs.index(o) for o in outs], [refs.index(i) for i in ins]] = A.T
    U = np.linalg.svd(R)[0][:, :, 0]  # dominant left singular vector per mode
    shapes = np.array([_real_shape(u) for u in U])
    mass = _modal_masses(R, shapes, dofs, refs, poles.imag)
    first = [outs.index(d) for d in dofs]
    synth = np.zeros(frf.H.shape, complex)
    synth[live] = synth_live  # NaN outside the band; DOFs that never move: 0
    log.info("ema pose %s: %d modes from %d FRFs in %d band%s", frf.pose, len(poles),
             int(live.sum()), len(bands), "s" if len(bands) > 1 else "")
    return PoseModes(frf, fn, zeta, frf.out_nodes[live][first], frf.out_dirs[live][first],
                     shapes, synth, stable, diagram, mass, tuple(bands), W is not None)


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
        """Modes per pose (frequency, damping ratio) and the FRF fit's error; then how
        each pose's band was fitted (sub-bands, coherence weights)."""
        from ...fe.text import text_table

        rows, notes = [], []
        for pm in self.poses:
            ok = np.isfinite(pm.synthesised)  # NaN: lines outside the fitted band
            err = np.linalg.norm((pm.synthesised - pm.frf.H)[ok]) / np.linalg.norm(
                pm.frf.H[ok])
            for r, (f, z) in enumerate(zip(pm.freq_hz, pm.damping, strict=True)):
                rows.append([pm.frf.pose, r + 1, f, 100 * z, 100 * err if r == 0 else ""])
            cuts = ", ".join(f"{b.core_lo:.1f}" for b in pm.bands[1:])
            notes.append(f"fit of pose {pm.frf.pose}: "
                         + (f"{len(pm.bands)} sub-bands cut at {cuts} Hz" if cuts else
                            "one band")
                         + ("; lines weighted by their coherence" if pm.weighted else ""))
        return "\n".join([text_table(["pose", "mode", "freq_Hz", "zeta_%", "fit_err_%"], rows,
                                      "{:.3f}"), *notes])

    def write_plots(self, stem) -> list:
        """``<stem>.stabilisation_<pose>.png`` and ``<stem>.frf_<pose>.png`` per pose."""
        from .ema_plots import plot_stabilisation, plot_synthesis

        out = []
        for pm in self.poses:
            out.append(plot_stabilisation(f"{stem}.stabilisation_{pm.frf.pose}.png", pm))
            out.append(plot_synthesis(f"{stem}.frf_{pm.frf.pose}.png", pm))
        return out


def _what_it_holds(content) -> str:
    """What a universal file without FRFs holds instead, and where that goes."""
    parts = [f"{len(content.shapes.freq_hz)} mode shapes"] if content.shapes is not None else []
    parts += ["test geometry"] if len(content.nodes) or content.geometry else []
    held = f", only {' and '.join(parts)}" if parts else ""
    return held + ("; mode shapes go to 'flexarm compare' as they are"
                   if content.shapes is not None else "")


def run_ema(path: PathType | list, f_lo: float | None = None, f_hi: float | None = None,
            max_order: int = 40, min_stable: float = 0.25,
            uff: UffOptions | None = None, *, split: str | int = "auto",
            weighted: bool = True) -> EmaResult:
    """Identify modes from the 58 FRFs of a universal file (or a list of
    :class:`UffFrf`), pose by pose (:func:`identify_modes`, with its ``split`` and
    ``weighted``); ``uff`` says what the file does not (the pose it was measured at,
    what its ordinates are)."""
    geometry = ()
    held = ""
    if isinstance(path, list | tuple):
        frfs = list(path)
    else:
        uff = uff or UffOptions()
        label, q = uff.pose if uff.pose is not None else (None, None)
        content = read_uff(path, label, q, uff.response)
        frfs, geometry = list(content.frfs), content.geometry
        held = _what_it_holds(content)
    if not frfs:
        raise ValueError(f"{path}: no FRFs (58 datasets) to identify modes from{held}; "
                         "export the measured FRFs (H1/H2, function type 4) for ema")
    return EmaResult(tuple(identify_modes(f, f_lo, f_hi, max_order, min_stable, split=split,
                                          weighted=weighted) for f in frfs), geometry)
