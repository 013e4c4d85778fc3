"""Predictions vs measured mode shapes: MAC pairing, AutoMAC, CoMAC per point.

Per pose, the model's shapes at the measured DOFs (:func:`~.shapes.model_shapes`, at
the measurement points of a :class:`~.shape_data.Points` table) are correlated with the
measured ones (:mod:`~.mac`): every measured mode is paired by MAC with frequency as a
tie-break, or reported unpaired when no model mode reaches the threshold; the
frequency-only assignment of :func:`~.modal.match_modes` is shown next to it, so a
swap of two close modes is visible.  CoMAC over the pairs shows where the model fails.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ...assembly.effects import apply_effects
from ...assembly.linkflex import links_arm, split_links
from ...assembly.system import ArmModel
from ...fe.errors import ReadError
from ...fe.files import writes_folder
from ...fe.text import text_table
from ...fe.typing import PathType
from ..data.formats.csv_points import read_points
from ..data.shape_data import Points, ShapeData
from .mac import (
    FREQ_RATIO,
    MAC_THRESHOLD,
    automac,
    comac,
    mac,
    moving_points,
    pair_modes,
    plot_mac,
    real_shapes,
    reversed_channels,
)
from .modal import match_modes
from .shapes import default_points, model_shapes

__all__ = ["PoseCorrelation", "ShapeComparison", "compare_shapes", "measurement_points",
           "shape_builds", "compare_with_models"]

#: Model modes computed beyond the measured count, so a pairing can skip some [-].
_EXTRA_MODES = 4


@dataclass(frozen=True, eq=False)
class PoseCorrelation:
    """Measured and model shapes of one pose.

    Attributes
    ----------
    pose : str
    f_meas, f_model : (nA,), (nB,) float
        Measured and model frequencies [Hz].
    mac : (nA, nB) float
        MAC matrix (rows measured, columns model).
    automac : (nA, nA) float
        MAC of the measured set with itself.
    model : (nA,) int
        Model mode (0-based) paired with each measured mode by MAC, -1 unpaired.
    pair_mac : (nA,) float
        MAC of each pair (best candidate when unpaired).
    by_frequency : (nA,) int
        Model mode a frequency-only assignment gives (-1 outside its window).
    nodes : (k,) int
        Measurement points.
    comac : (k,) float
        CoMAC of each point over the paired modes.
    moving : (k,) bool
        The point moves at least 10 % of the most-moving one (:func:`~.mac.moving_points`):
        only those can be "the worst" (a point at rest has a CoMAC of noise).
    paired_shapes : (A, B)
        Each measured shape (real) and the model shape most like it within the
        frequency window, (nA, m) each: what a reversed channel is judged on.
    """

    pose: str
    f_meas: np.ndarray
    f_model: np.ndarray
    mac: np.ndarray
    automac: np.ndarray
    model: np.ndarray
    pair_mac: np.ndarray
    by_frequency: np.ndarray
    nodes: np.ndarray
    comac: np.ndarray
    moving: np.ndarray = None
    paired_shapes: tuple = ()

    @property
    def swapped(self) -> np.ndarray:
        """(nA,) bool: MAC pairing and frequency-only assignment disagree."""
        return (self.model >= 0) & (self.model != self.by_frequency)


@dataclass(frozen=True, eq=False)
class ShapeComparison:
    """Result of :func:`compare_shapes`: one :class:`PoseCorrelation` per pose."""

    poses: tuple
    threshold: float = MAC_THRESHOLD
    label: str = "model"
    dofs: tuple = ()

    def reversed_channels(self) -> list[str]:
        """One line per channel whose sign flip raises the mean MAC of the measured modes
        with their most alike model modes, over every pose (:func:`~.mac.reversed_channels`):
        a sensor mounted the wrong way round."""
        pairs = [pc.paired_shapes for pc in self.poses if len(pc.paired_shapes)
                 and len(pc.paired_shapes[0])]
        if not pairs or not self.dofs:
            return []
        A = np.concatenate([a for a, _ in pairs])
        B = np.concatenate([b for _, b in pairs])
        return [f"channel {self.dofs[i]} looks reversed: flipping its sign raises the mean "
                f"MAC from {before:.3f} to {after:.3f}"
                for i, before, after in reversed_channels(A, B)]

    def text(self) -> str:
        """Pairs per pose (measured and model mode, frequencies, MAC), unpaired modes,
        the largest off-diagonal AutoMAC and the lowest-CoMAC points."""
        lines = []
        for pc in self.poses:
            rows = []
            for j, (fa, k, m, kf) in enumerate(zip(pc.f_meas, pc.model, pc.pair_mac,
                                                   pc.by_frequency, strict=True)):
                fb = pc.f_model[k] if k >= 0 else np.nan
                note = "unpaired" if k < 0 else (f"freq-only: {kf + 1 if kf >= 0 else 'none'}"
                                                 if kf != k else "")
                rows.append([pc.pose, j + 1, fa, k + 1 if k >= 0 else "-", fb,
                             100 * (fb - fa) / fa, m, note])
            lines.append(text_table(["pose", "mode", "meas_Hz", "model", "model_Hz", "dev_%",
                                     "MAC", "note"], rows, "{:.3f}"))
            off = pc.automac - np.eye(len(pc.automac))
            worst = np.unravel_index(np.argmax(off), off.shape) if off.size else (0, 0)
            lines.append(f"{pc.pose}: AutoMAC largest off-diagonal {off.max(initial=0):.3f} "
                         f"(modes {worst[0] + 1} and {worst[1] + 1})")
            moving = np.ones(len(pc.comac), bool) if pc.moving is None else pc.moving
            order = [i for i in np.argsort(np.where(moving, pc.comac, np.inf))[:3] if moving[i]]
            lines.append(f"{pc.pose}: lowest CoMAC at nodes that move " + ", ".join(
                f"{pc.nodes[i]} ({pc.comac[i]:.3f})" for i in order))
        lines += self.reversed_channels()
        n_un = sum(int(np.sum(pc.model < 0)) for pc in self.poses)
        lines.append(f"{n_un} measured mode(s) without a model partner at MAC >= "
                     f"{self.threshold:g}" if n_un else
                     f"every measured mode paired at MAC >= {self.threshold:g}")
        return "\n".join(lines)

    @writes_folder()
    def write(self, folder: PathType) -> list[Path]:
        """``mac.csv`` (every entry), ``pairs.csv``, ``comac.csv`` and per pose
        ``mac_<pose>.png`` and ``automac_<pose>.png`` into ``folder``."""
        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        out = [folder / "mac.csv", folder / "pairs.csv", folder / "comac.csv"]
        with open(out[0], "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["pose", "meas_mode", "meas_Hz", "model_mode", "model_Hz", "mac"])
            for pc in self.poses:
                for (i, j), v in np.ndenumerate(pc.mac):
                    w.writerow([pc.pose, i + 1, pc.f_meas[i], j + 1, pc.f_model[j], v])
        with open(out[1], "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["pose", "meas_mode", "meas_Hz", "model_mode", "model_Hz", "mac",
                        "freq_only_model_mode"])
            for pc in self.poses:
                for i, k in enumerate(pc.model):
                    w.writerow([pc.pose, i + 1, pc.f_meas[i], k + 1 if k >= 0 else "",
                                pc.f_model[k] if k >= 0 else "", pc.pair_mac[i],
                                pc.by_frequency[i] + 1 if pc.by_frequency[i] >= 0 else ""])
        with open(out[2], "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["pose", "node", "comac"])
            for pc in self.poses:
                w.writerows([pc.pose, int(n), c] for n, c in zip(pc.nodes, pc.comac,
                                                                strict=True))
        for pc in self.poses:
            out.append(folder / f"mac_{pc.pose}.png")
            plot_mac(out[-1], pc.mac, pc.f_meas, pc.f_model,
                     f"MAC, measured vs {self.label}, pose {pc.pose}")
            out.append(folder / f"automac_{pc.pose}.png")
            plot_mac(out[-1], pc.automac, pc.f_meas, pc.f_meas, f"AutoMAC, pose {pc.pose}",
                     "measured", "measured")
        return out


def _pose(arm: ArmModel, data: ShapeData, rows: np.ndarray, points: Points, builds,
          threshold: float) -> PoseCorrelation:
    n = arm.chain.n_joints
    q = data.q[rows[0], :n]
    f_model, _, B = model_shapes(arm, q, points, data.nodes, data.dirs,
                                 len(rows) + _EXTRA_MODES, builds)
    A = data.shapes[rows]
    f_meas = data.freq_hz[rows]
    M = mac(A, B)
    pairing = pair_modes(M, f_meas, f_model, threshold)
    ok = pairing.paired
    near = np.maximum(f_model[None, :] / f_meas[:, None],
                      f_meas[:, None] / f_model[None, :]) <= FREQ_RATIO
    nodes = list(dict.fromkeys(data.nodes.tolist()))
    cm = comac(A[ok], B[pairing.model[ok]], data.nodes) if ok.any() else np.zeros(len(nodes))
    return PoseCorrelation(str(data.poses[rows[0]]), f_meas, f_model, M, automac(A),
                           pairing.model, pairing.mac, match_modes(f_meas, f_model),
                           np.array(nodes), cm, moving_points(A, data.nodes),
                           (real_shapes(A), B[np.argmax(np.where(near, M, -1.0), axis=1)]))


def compare_shapes(arm: ArmModel, data: ShapeData, points: Points, effects=(),
                   flexible: ArmModel | None = None, builds=None,
                   threshold: float = MAC_THRESHOLD) -> ShapeComparison:
    """Correlate the mode shapes of ``arm`` (plus ``effects``) with measured ``data``.

    Parameters
    ----------
    arm : ArmModel
        The model (E-model, or Guyan/CB with ``builds`` for the links' recovery).
    data : ShapeData
        Measured frequencies and shapes.
    points : Points
        Where the measured nodes sit on the arm.
    effects, flexible
        As for :func:`~.compare.compare_modal`.
    threshold : float
        MAC a pair needs.

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> from flexarm.validation.lab.modal_lab import virtual_shapes
    >>> arm = two_link_arm()
    >>> pts = Points(nodes=[1, 2], links=[1, 2], positions=[[0.5, 0, 0], [1.0, 0, 0]])
    >>> data = virtual_shapes(arm, {"A": np.array([0.0, 0.3])}, pts, n_modes=2)
    >>> pc = compare_shapes(arm, data, pts).poses[0]
    >>> pc.model.tolist(), bool(np.all(np.diag(pc.mac) > 0.99))
    ([0, 1], True)
    """
    c, rest = split_links(effects)
    model = apply_effects(links_arm(arm, flexible, c), rest)[0]
    labels = list(dict.fromkeys(data.poses.tolist()))
    return ShapeComparison(tuple(_pose(model, data, data.pose_rows(p), points, builds,
                                       threshold) for p in labels), threshold,
                           dofs=tuple(f"node {n} {d}" for n, d in zip(data.nodes, data.dirs,
                                                                       strict=True)))


def measurement_points(data_path: PathType | None, robot, nodes=None, at=None) -> Points:
    """The points table of a measurement file: ``<stem>.points.csv`` next to it (as
    ``lab`` writes it), else, given ``at`` = (pose, q [rad]) of its first pose, the one
    its universal-file geometry gives (:func:`~.point_geometry.file_points`), else the
    robot's default points (:func:`~.shapes.default_points`).  A link the robot does not
    have is refused at its line; with ``nodes`` (the file's), a node the table lacks is
    refused naming both files."""
    if data_path is None or not Path(data_path).with_suffix(".points.csv").exists():
        from .point_geometry import file_points

        found = None if data_path is None or at is None else file_points(data_path, robot, *at)
        return default_points(robot) if found is None else found
    side = Path(data_path).with_suffix(".points.csv")
    points = read_points(side, len(robot.links))
    missing = [] if nodes is None else np.setdiff1d(np.asarray(nodes, np.int64), points.nodes)
    if len(missing):
        raise ReadError(f"{side}: node {missing[0]} of {Path(data_path).name} is not in it "
                        f"(it has {', '.join(str(n) for n in points.nodes)}): add a row "
                        "node, link, x_mm, y_mm, z_mm for every node of the file")
    return points


def shape_builds(models, options):
    """The link builds whose recovery gives shapes at points (None for rigid links): of
    the compared model when it has flexible links (Guyan/CB), else of the coarse
    flexible model of the link-flexibility effect, when built (both from the
    superelement cache)."""
    from ...assembly.arm import ArmSpec, build_arm

    if not all(b.is_rigid for b in models.arm.bodies):
        spec = ArmSpec(options.model, options.mass, options.mesh_size, options.n_modes,
                       options.coupling)
        return build_arm(models.robot, spec).builds
    if models.flexible is not None:
        spec = ArmSpec("cb", mesh_size=options.flex_mesh, n_modes=options.flex_modes)
        return build_arm(models.robot, spec).builds
    return None


def compare_with_models(models, options, data: ShapeData,
                        data_path: PathType | None = None) -> ShapeComparison:
    """:func:`compare_shapes` on the models of a validation run
    (:class:`~.models.ValidationModels`): the points table of ``data_path``
    (:func:`measurement_points`) and the builds of :func:`shape_builds`."""
    label = {"emodel": "E-model", "guyan": "Guyan", "cb": "CB"}.get(options.model, "model")
    cmp = compare_shapes(models.arm, data, measurement_points(
                             data_path, models.robot, data.nodes,
                             (str(data.poses[0]), data.q[0])),
                         models.effects_with_links(), models.flexible,
                         shape_builds(models, options))
    return replace(cmp, label=label)
