"""The 58 datasets of a universal file: frequency response functions turned into
receptance [m/N] (see :mod:`.uff` for the conventions), one :class:`UffFrf` per pose."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ....fe.errors import ReadError
from ...tolerances import tol
from ..measurements import DIRECTIONS, FrfData

__all__ = ["UffFrf", "RESPONSES", "COHERENCE", "Where", "frf_of", "coherence_of", "collect_frfs",
           "direction"]

_RESPONSE = {8: 0, 11: 1, 12: 2}  # ordinate type -> power of i*omega that divides it
#: ``--response`` names of the ordinate types.
RESPONSES = {"displacement": 8, "velocity": 11, "acceleration": 12}
_GENERAL = (0, 1)  # unknown, general: the unit label or the caller says what it is
_FORCE = (0, 13)  # unknown or force


class Where:
    """Error messages naming the file, the dataset and the field."""

    def __init__(self, path: Path):
        self.path = path

    def error(self, i: int, kind: int, name: str, message: str) -> ReadError:
        return ReadError(f"{self.path}, dataset {i + 1} (type {kind}), field '{name}': "
                         f"{message}")


@dataclass(frozen=True, eq=False)
class UffFrf:
    """FRFs of one pose from 58 datasets, receptance in the base frame.

    Attributes
    ----------
    pose : str
    q : (6,) float
        Joint angles [rad] (zeros when neither the file nor the caller gave them).
    freq_hz : (nf,) float
        Frequency lines [Hz], shared by every FRF.
    out_nodes, in_nodes : (n,) int
        Response and reference node of each FRF.
    out_dirs, in_dirs : (n,) str
        Their directions, ``x``, ``y`` or ``z`` (positive).
    H : (n, nf) complex
        Receptance [m/N].
    coherence : (n, nf) float or None
        Ordinary coherence ``gamma^2`` [-] of each FRF at its lines (58 sets of function
        type 6), when the file has one for every FRF of the pose.
    """

    pose: str
    q: np.ndarray
    freq_hz: np.ndarray
    out_nodes: np.ndarray
    out_dirs: np.ndarray
    in_nodes: np.ndarray
    in_dirs: np.ndarray
    H: np.ndarray
    coherence: np.ndarray | None = None

    def matrix(self) -> tuple[list[str], list[str], np.ndarray]:
        """Output DOF labels, input DOF labels and (nf, n_out, n_in) receptance [m/N]
        (NaN where the file has no FRF for the pair)."""
        outs = [f"{n}{d}" for n, d in zip(self.out_nodes, self.out_dirs, strict=True)]
        ins = [f"{n}{d}" for n, d in zip(self.in_nodes, self.in_dirs, strict=True)]
        uo, ui = list(dict.fromkeys(outs)), list(dict.fromkeys(ins))
        A = np.full((len(self.freq_hz), len(uo), len(ui)), np.nan + 0j)
        A[:, [uo.index(o) for o in outs], [ui.index(i) for i in ins]] = self.H.T
        return uo, ui, A

    def to_frf_data(self, node: int | None = None) -> FrfData:
        """The FRFs at one node (the TCP) as :class:`FrfData`; ``node`` None: the
        only node the FRFs use."""
        nodes = np.unique(np.r_[self.out_nodes, self.in_nodes])
        if node is None:
            if len(nodes) != 1:
                raise ValueError(f"the FRFs of pose '{self.pose}' use nodes "
                                 f"{', '.join(map(str, nodes))}: name the TCP node, "
                                 f"--tcp-node N")
            node = int(nodes[0])
        keep = (self.out_nodes == node) & (self.in_nodes == node)
        if not keep.any():
            raise ValueError(f"the FRFs of pose '{self.pose}' have no driving-point FRF at "
                             f"node {node} (nodes {', '.join(map(str, nodes))})")
        nf, k = len(self.freq_hz), int(keep.sum())
        return FrfData(poses=[self.pose] * (nf * k), q=np.tile(self.q, (nf * k, 1)),
                       inputs=np.repeat(self.in_dirs[keep], nf),
                       outputs=np.repeat(self.out_dirs[keep], nf),
                       freq_hz=np.tile(self.freq_hz, k), receptance=self.H[keep].ravel(),
                       coherence=None if self.coherence is None else self.coherence[keep].ravel())


def _ordinate(where: Where, i: int, dset: dict, response: str | None) -> int:
    """The ordinate's type (8, 11, 12): the file's, else its unit label's, else the
    caller's ``response``."""
    spec = int(dset.get("ordinate_spec_data_type", 8))
    if spec in _RESPONSE:
        return spec
    if spec not in _GENERAL:
        raise where.error(i, 58, "ordinate_spec_data_type", f"ordinate type {spec} is not "
                          "displacement (8), velocity (11) or acceleration (12)")
    if response is not None:
        return RESPONSES[response]
    label = str(dset.get("ordinate_axis_units_lab", "")).replace(" ", "").lower()
    for marks, code in ((("s^2", "s²", "s**2", "/g"), 12), (("m/s",), 11), (("m",), 8)):
        if any(k in label for k in marks):
            return code
    raise where.error(i, 58, "ordinate_spec_data_type", f"ordinate type {spec} "
                      f"({'general' if spec else 'unknown'}) with unit label {label!r}: say what "
                      "the response is, --response displacement|velocity|acceleration")


def direction(where: Where, i: int, name: str, code) -> tuple[str, float]:
    """(axis ``x``/``y``/``z``, sign) of a UFF direction code; anything but a translation
    (a scalar channel, a rotation) is refused with the fix."""
    code = int(code)
    if abs(code) not in (1, 2, 3):
        what = "a scalar channel without an axis" if code == 0 else "a rotation"
        raise where.error(i, 58, name, f"direction {code} is {what}: flexarm compares "
                          "translations along x, y, z (±1, ±2, ±3); export the FRFs with "
                          "their directions")
    return DIRECTIONS[abs(code) - 1], float(np.sign(code))


#: 58 function types that are not FRFs, named in the refusal.
_FUNCTIONS = {1: "time histories", 2: "auto-spectra", 3: "cross-spectra", 6: "coherence",
              9: "power spectral densities"}


def frf_of(where: Where, i: int, dset: dict, factor: float, response: str | None = None):
    """(freq [Hz], receptance [m/N]) of one 58 set (positive directions); the 0 Hz line of
    a velocity or acceleration FRF is dropped."""
    func = int(dset.get("func_type", -1))
    if func != 4:
        what = _FUNCTIONS.get(func, f"function type {func}")
        raise where.error(i, 58, "func_type", f"{what}, not frequency response functions "
                          "(type 4): measure or export FRFs (H1/H2) for ema and compare")
    spec = _ordinate(where, i, dset, response)
    if int(dset.get("orddenom_spec_data_type", 13)) not in _FORCE:
        raise where.error(i, 58, "orddenom_spec_data_type", "the denominator must be a force "
                          f"(13), got {dset.get('orddenom_spec_data_type')}")
    freq = np.asarray(dset["x"], float)
    data = np.asarray(dset["data"])
    if not np.iscomplexobj(data):
        raise where.error(i, 58, "ord_data_type", "FRF data must be complex (5 or 6)")
    for name, values in (("x", freq), ("data", data)):
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            k = int(bad[0])
            at = f"line {k + 1}" + (f" ({freq[k]:g} Hz)" if np.isfinite(freq[k]) else "")
            raise where.error(i, 58, name, f"{len(bad)} value{'s' if len(bad) > 1 else ''} "
                              f"not finite, the first at frequency {at}: {values[k]}")
    power = _RESPONSE[spec]
    if power and np.any(freq <= 0):  # an analyzer's 0 Hz line: no receptance there
        if np.any(np.diff(freq) <= 0) or np.sum(freq <= 0) > 1:
            raise where.error(i, 58, "x", "lines at or below 0 Hz besides the first: a "
                              "velocity or acceleration FRF has no receptance there")
        freq, data = freq[1:], data[1:]
    if freq.size < tol.frf_min_lines:
        raise where.error(i, 58, "x", f"{freq.size} frequency line{'s' if freq.size != 1 else ''}"
                          f"; an FRF needs at least {tol.frf_min_lines} (a peak needs a line "
                          "on each side)")
    H = data * factor / (2j * np.pi * np.where(freq > 0, freq, 1.0)) ** power
    _, s_out = direction(where, i, "rsp_dir", dset["rsp_dir"])
    _, s_in = direction(where, i, "ref_dir", dset["ref_dir"])
    return freq, H * s_out * s_in


#: 58 function type of the ordinary coherence.
COHERENCE = 6


def coherence_of(where: Where, i: int, dset: dict) -> tuple[np.ndarray, np.ndarray]:
    """(freq [Hz], gamma^2 [-]) of a 58 coherence set; values must lie in [0, 1]."""
    freq, g2 = np.asarray(dset["x"], float), np.asarray(dset["data"])
    top = 1 + tol.coherence_round_off
    if np.iscomplexobj(g2) or np.any(~np.isfinite(g2)) or np.any((g2 < 0) | (g2 > top)):
        raise where.error(i, 58, "data", "a coherence must be real, between 0 and 1: export "
                          "the ordinary coherence (gamma squared)")
    return freq, np.minimum(g2.astype(float), 1.0)


def _key(d: dict) -> tuple:
    return (int(d["rsp_node"]), abs(int(d["rsp_dir"])), int(d["ref_node"]),
            abs(int(d["ref_dir"])))


def _coherence(where: Where, mine: list, freq: np.ndarray, found: list) -> np.ndarray | None:
    """(n, nf) coherence of a pose's FRF items at their lines ``freq`` from the
    (index, dset, pose, freq, gamma^2) items ``found``; None unless every FRF has one."""
    by_key = {_key(c[1]): c for c in found}
    if not found or any(_key(it[1]) not in by_key for it in mine):
        return None
    rows = []
    for it in mine:
        i, _, _, cf, g2 = by_key[_key(it[1])]
        k = np.clip(np.searchsorted(cf, freq), 0, len(cf) - 1)
        if not np.allclose(cf[k], freq, rtol=1e-9, atol=0):
            raise where.error(i, 58, "x", f"the coherence's lines do not cover those of its "
                              f"FRF (dataset {it[0] + 1})")
        rows.append(g2[k])
    return np.array(rows)


def collect_frfs(where: Where, items: list, coherence: list = ()) -> tuple[UffFrf, ...]:
    """One :class:`UffFrf` per pose from (index, dset, pose, q, freq, H) items, with the
    coherence of (index, dset, pose, freq, gamma^2) items matched by nodes and axes."""
    out = []
    for label in dict.fromkeys(it[2] for it in items):
        mine = [it for it in items if it[2] == label]
        i0, _, _, q, freq, _ = mine[0]
        for i, _, _, _, f, _ in mine[1:]:
            if f.shape != freq.shape or not np.array_equal(f, freq):
                raise where.error(i, 58, "x", f"frequency lines differ from dataset {i0 + 1} "
                                  f"of the same pose '{label}'")
        d = [it[1] for it in mine]
        out.append(UffFrf(
            label, q, freq,
            np.array([int(s["rsp_node"]) for s in d]),
            np.array([direction(where, it[0], "rsp_dir", it[1]["rsp_dir"])[0] for it in mine]),
            np.array([int(s["ref_node"]) for s in d]),
            np.array([direction(where, it[0], "ref_dir", it[1]["ref_dir"])[0] for it in mine]),
            np.array([it[5] for it in mine]),
            _coherence(where, mine, freq, [c for c in coherence if c[2] == label])))
    return tuple(out)
