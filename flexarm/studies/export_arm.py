"""Export the arm at a pose for the tools engineers simulate with.

``"ss"``: the state-space model (:mod:`~flexarm.assembly.state_space`) as MATLAB
``.mat`` or NumPy ``.npz``, checked against :func:`~flexarm.assembly.analyses.frf` on a
frequency grid before anything is written.  ``"op4"``: the reduced arm's ``K``, ``M``,
damping and TCP map as Nastran OP4 (:mod:`~flexarm.assembly.formats.op4`), and every
link superelement as ``<stem>_<link>.op4`` next to it
(:mod:`~flexarm.reduction.formats.op4`).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..assembly.analyses import frf
from ..assembly.arm import Arm
from ..assembly.arm_matrices import arm_matrices
from ..assembly.formats import matrices_registry, state_space_registry
from ..assembly.formats.op4 import dof_table_path
from ..assembly.state_space import ArmStateSpace, state_space
from ..fe.typing import ArrayLike
from ..reduction import formats as se_formats

__all__ = ["EXPORT_FORMATS", "ArmExport", "export_arm", "export_format"]

log = logging.getLogger(__name__)

#: What ``export_arm`` writes: a state-space model or the arm's matrices as OP4.
EXPORT_FORMATS = ("ss", "op4")
#: Frequencies of the self-check of a state-space export [-].
_N_CHECK = 40


@dataclass(frozen=True, eq=False)
class ArmExport:
    """What :func:`export_arm` wrote.

    Attributes
    ----------
    paths : tuple of Path
    file_format : {"ss", "op4"}
    state_space : ArmStateSpace or None
        The exported model (``"ss"``).
    frf_error : float
        ``max |H_ss - H_frf| / max |H_frf|`` over the TCP block on the check grid [-]
        (``"ss"``; NaN for ``"op4"``).
    n_dofs : int
        Coordinates of the exported model (``"op4"``) or states (``"ss"``).
    """

    paths: tuple[Path, ...]
    file_format: str
    state_space: ArmStateSpace | None
    frf_error: float
    n_dofs: int

    def text(self) -> str:
        """A few lines: what was written and the FRF self-check."""
        if self.state_space is not None:
            lines = self.state_space.text().splitlines()[:3]
            lines.append(f"state-space FRF vs frf: max relative difference "
                         f"{self.frf_error:.1e} ({_N_CHECK} frequencies)")
            return "\n".join(lines)
        return f"arm matrices: {self.n_dofs} coordinates (KAAX, MAAX, BAAX, GTCP)"


def export_format(path, file_format: str | None = None, model: str | None = None) -> str:
    """``"ss"`` or ``"op4"`` for ``path`` (``file_format`` wins); a bad extension, or OP4
    of the full-FE arm (``model="full"``), raises ``ValueError`` before any work."""
    if file_format is None:
        file_format = "op4" if Path(path).suffix.lower() == ".op4" else "ss"
    if file_format not in EXPORT_FORMATS:
        raise ValueError(f"export format must be one of {', '.join(EXPORT_FORMATS)}, "
                         f"got '{file_format}'")
    reg = state_space_registry if file_format == "ss" else matrices_registry
    reg.format_of(path, mode="w")
    if file_format == "op4" and model == "full":
        raise ValueError("OP4 of the full-FE arm: export a reduced model (emodel, guyan, cb), "
                         "whose links come along as superelements")
    return file_format


def _frf_error(arm: Arm, q: np.ndarray, ss: ArmStateSpace) -> float:
    top = 1.5 * float(ss.freq_hz[min(ss.n_modes, 12) - 1])
    f = np.geomspace(0.2, top, _N_CHECK)
    H = frf(arm.model, q, f)
    Hs = ss.frequency_response(f)[:, :6, :6]
    return float(np.abs(Hs - H).max() / np.abs(H).max())


def export_arm(arm: Arm, q: ArrayLike, path, file_format: str | None = None,
               n_modes: int | None = None) -> ArmExport:
    """Write ``arm`` at pose ``q`` (n,) [rad] to ``path``.

    ``file_format``: ``"ss"`` (``.mat``/``.npz``) or ``"op4"`` (``.op4``); by default
    from the extension.  ``n_modes`` truncates a state-space model (static residual in
    ``D``).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from flexarm.assembly.arm import build_arm
    >>> from flexarm.robot import load_robot
    >>> robot = load_robot()
    >>> ex = export_arm(build_arm(robot), robot.pose("P1"),
    ...                 pathlib.Path(tempfile.mkdtemp()) / "arm_P1.npz")
    >>> ex.state_space.A.shape, ex.frf_error < 1e-10
    ((24, 24), True)
    """
    q = np.asarray(q, dtype=float)
    path = Path(path)
    fmt = export_format(path, file_format)
    if fmt == "ss":
        ss = state_space(arm.model, q, n_modes, model=arm.spec.label)
        err = _frf_error(arm, q, ss) if n_modes is None else float("nan")
        state_space_registry.write(path, ss)
        log.info("state space of %s written to %s", arm.spec.label, path)
        return ArmExport((path,), fmt, ss, err, ss.A.shape[0])
    am = arm_matrices(arm.model, q, arm.spec.label)
    matrices_registry.write(path, am)
    paths = [path, dof_table_path(path)]
    for lb, link in zip(arm.builds or (), arm.robot.links, strict=False):
        if lb.superelement is not None:
            paths.append(se_formats.write(path.with_name(f"{path.stem}_{link.name}.op4"),
                                          lb.superelement, "op4"))
    return ArmExport(tuple(paths), fmt, None, float("nan"), am.K.shape[0])
