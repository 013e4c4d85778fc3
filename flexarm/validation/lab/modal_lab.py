"""The modal lab: measured-like natural frequencies, mode shapes and FRFs of a model with
hidden effects and noise, as a vibration test at the arm's poses would give them."""

from __future__ import annotations

import logging

import numpy as np

from ...assembly.analyses import natural_frequencies
from ...assembly.effects import apply_effects, at_pose
from ...assembly.linkflex import links_arm, split_links
from ...assembly.system import ArmModel
from ...robot.effects import Effect
from ..data.measurements import DIRECTIONS, ModalData
from ..data.shape_data import Points, ShapeData
from ..tolerances import tol

__all__ = ["virtual_modal", "virtual_shapes", "virtual_frfs"]

log = logging.getLogger(__name__)


def virtual_modal(arm: ArmModel, poses: dict, effects: list[Effect] = (), n_modes: int = 4,
                  freq_noise: float = tol.freq_noise, seed: int = 0,
                  flexible: ArmModel | None = None) -> ModalData:
    """Measured-like natural frequencies of ``arm`` with ``effects`` (relative noise).

    Nonlinear joint laws do not enter (small-amplitude modal tests about the pose).

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> arm = two_link_arm()
    >>> q = np.zeros(arm.chain.n_joints)
    >>> virtual_modal(arm, {"A": q}, n_modes=2, freq_noise=0.0).freq_hz.shape
    (2,)
    """
    c, rest = split_links(effects)
    truth, _ = apply_effects(links_arm(arm, flexible, c), rest)
    names = list(poses)
    Q = np.array([np.asarray(poses[p], float) for p in names])
    F = np.array([np.atleast_1d(natural_frequencies(at_pose(truth, rest, q), q))[:n_modes]
                  for q in Q])
    rng = np.random.default_rng(seed)
    F = F * (1 + freq_noise * rng.standard_normal(F.shape))
    n = F.shape[1]
    q6 = np.zeros((len(names), 6))
    q6[:, :Q.shape[1]] = Q
    log.info("virtual modal lab: %d poses x %d modes", len(names), n)
    return ModalData(poses=np.repeat(names, n), q=np.repeat(q6, n, axis=0),
                     modes=np.tile(np.arange(1, n + 1), len(names)), freq_hz=F.ravel())


def _truth(arm: ArmModel, effects, flexible: ArmModel | None) -> ArmModel:
    c, rest = split_links(effects)
    return apply_effects(links_arm(arm, flexible, c), rest)[0]


def virtual_shapes(arm: ArmModel, poses: dict, points: Points, effects: list[Effect] = (),
                   n_modes: int = 6, freq_noise: float = tol.freq_noise,
                   shape_noise: float = 0.0, seed: int = 0, flexible: ArmModel | None = None,
                   builds=None) -> ShapeData:
    """Measured-like frequencies, damping ratios and mode shapes at every point (x, y,
    z) of ``arm`` with ``effects``: relative frequency noise, and shape noise
    ``shape_noise`` times each shape's largest entry (independent per DOF).

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> pts = Points(nodes=[1, 2], links=[1, 2], positions=[[0.5, 0, 0], [1.0, 0, 0]])
    >>> s = virtual_shapes(two_link_arm(), {"A": np.zeros(2)}, pts, n_modes=2)
    >>> s.shapes.shape, s.dofs[:2]
    ((2, 6), ['1x', '1y'])
    """
    from ..dynamic.shapes import model_shape_data

    data = model_shape_data(_truth(arm, effects, flexible), poses, points, n_modes, builds,
                            effects)
    rng = np.random.default_rng(seed)
    f = data.freq_hz * (1 + freq_noise * rng.standard_normal(data.freq_hz.shape))
    peak = np.abs(data.shapes).max(axis=1, keepdims=True)
    phi = data.shapes + shape_noise * peak * rng.standard_normal(data.shapes.shape)
    log.info("virtual modal lab: %d poses x %d modes at %d DOFs", len(poses),
             len(data.freq_hz) // max(len(poses), 1), data.n_dofs)
    return ShapeData(poses=data.poses, q=data.q, modes=data.modes, freq_hz=f,
                     damping_ratio=data.damping_ratio, nodes=data.nodes, dirs=data.dirs,
                     shapes=phi)


def virtual_frfs(arm: ArmModel, poses: dict, points: Points, inputs, freq_hz,
                 effects: list[Effect] = (), noise: float = 0.02, seed: int = 0,
                 flexible: ArmModel | None = None, builds=None) -> list:
    """Measured-like receptances [m/N] at every point (x, y, z) per force at the
    ``inputs`` DOFs (``[(node, "y"), ...]``), one
    :class:`~flexarm.validation.data.formats.uff.UffFrf` per pose.

    Modal superposition over all modes with the model's modal damping; ``noise`` is a
    relative complex Gaussian error per frequency line, ``noise |H|`` (an averaged
    H1 estimate's scatter).
    """
    from ..data.formats.uff import UffFrf
    from ..dynamic.shapes import model_shapes

    truth = _truth(arm, effects, flexible)
    rng = np.random.default_rng(seed)
    out_nodes = np.repeat(points.nodes, 3)
    out_dirs = np.tile(list(DIRECTIONS), points.n_points)
    in_nodes = np.array([int(n) for n, _ in inputs])
    in_dirs = np.array([str(d) for _, d in inputs])
    w = 2 * np.pi * np.asarray(freq_hz, float)
    frfs = []
    for label, q in poses.items():
        f, zeta, phi = model_shapes(at_pose(truth, effects, q), q, points,
                                    np.r_[out_nodes, in_nodes],
                                    np.r_[out_dirs, in_dirs], None, builds)
        wr = 2 * np.pi * f
        den = wr[None, :] ** 2 - w[:, None] ** 2 + 2j * zeta * wr[None, :] * w[:, None]
        po, pi = phi[:, :len(out_nodes)], phi[:, len(out_nodes):]
        H = np.einsum("ro,fr,ri->oif", po, 1.0 / den, pi)  # (n_out, n_in, nf)
        H = H * (1 + noise / np.sqrt(2) * (rng.standard_normal(H.shape)
                                           + 1j * rng.standard_normal(H.shape)))
        q6 = np.zeros(6)
        q6[:len(q)] = q
        frfs.append(UffFrf(label, q6, np.asarray(freq_hz, float),
                           np.repeat(out_nodes, len(in_nodes)), np.repeat(out_dirs, len(in_nodes)),
                           np.tile(in_nodes, len(out_nodes)), np.tile(in_dirs, len(out_nodes)),
                           H.reshape(-1, len(w))))
    return frfs
