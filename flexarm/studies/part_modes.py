"""Natural frequencies of one meshed part, free or clamped.

A free part gets its six rigid-body modes first (computed with an automatic negative
shift, so they come out as near-zero eigenvalues); a clamped part has its selected
nodes fixed in all three directions and the shift at zero.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..fe import (
    Material,
    TetMesh,
    assemble,
    dof_split,
    mass_properties,
    modes,
    node_dofs,
    select_nodes,
    shift_invert,
)
from ..fe.eigen import DENSE_LIMIT
from ..fe.files import atomic_path
from ..fe.text import text_table
from ..fe.typing import FloatArray, IntArray

__all__ = ["PartModes", "part_modes", "mode_limit"]

log = logging.getLogger(__name__)

#: Rigid-body modes of a free part.
N_RIGID = 6


@dataclass(frozen=True, eq=False)
class PartModes:
    """Frequencies of a part and how it was supported.

    Attributes
    ----------
    freq_hz : (k,) float
        Natural frequencies [Hz], rigid-body modes (0 Hz to round-off) first.
    is_rigid : (k,) bool
    n_dofs : int
        FE DOFs of the part (3 per node).
    mass : float
        Mass of the solid [kg].
    clamped : (c,) int
        Fixed nodes (empty for a free part).
    fix : str or None
        The selection that fixed them.
    """

    freq_hz: FloatArray
    is_rigid: np.ndarray
    n_dofs: int
    mass: float
    clamped: IntArray
    fix: str | None = None

    @property
    def is_free(self) -> bool:
        return self.clamped.size == 0

    @property
    def n_rigid(self) -> int:
        return int(np.count_nonzero(self.is_rigid))

    @property
    def first_elastic_hz(self) -> float:
        """The lowest non-rigid frequency [Hz]."""
        return float(self.freq_hz[~self.is_rigid][0])

    def support(self) -> str:
        """One line: ``free`` or ``clamped N nodes (selection)``."""
        return "free" if self.is_free else f"clamped {self.clamped.size} nodes ({self.fix})"

    def text(self) -> str:
        """The frequency table (mode, frequency [Hz], rigid marker)."""
        rows = [[i + 1, float(f), "rigid" if r else ""]
                for i, (f, r) in enumerate(zip(self.freq_hz, self.is_rigid, strict=True))]
        return text_table(["mode", "freq [Hz]", ""], rows)

    def write_csv(self, path) -> Path:
        """``mode,freq_Hz,rigid`` (one row per mode; rigid 0/1), written atomically."""
        with atomic_path(path) as tmp:
            tmp.write_text("mode,freq_Hz,rigid\n" + "".join(
                f"{i + 1},{float(f):.10g},{int(bool(r))}\n"
                for i, (f, r) in enumerate(zip(self.freq_hz, self.is_rigid, strict=True))))
        return Path(path)


def mode_limit(n_free_dofs: int, is_free: bool) -> int:
    """The most elastic modes :func:`part_modes` gives of a part with ``n_free_dofs``
    unconstrained DOF: all of a small part (solved densely), and of a larger one fewer
    than the sparse eigensolver's ``N - 1``: asking for more would solve for every mode of
    a dense matrix (1.6 GB at 6,000 DOF).

    Examples
    --------
    >>> mode_limit(5955, True), mode_limit(120, False)
    (5947, 120)
    """
    rigid = N_RIGID if is_free else 0
    usable = n_free_dofs if n_free_dofs <= DENSE_LIMIT else n_free_dofs - 2
    return max(usable - rigid, 0)


def part_modes(mesh: TetMesh, material: Material, n_modes: int = 10,
               fix: str | IntArray | None = None, backend: str | None = None,
               matrices=None, progress: Callable[[str], None] | None = None) -> PartModes:
    """The lowest ``n_modes`` elastic modes of a part (plus its rigid modes when free).

    Parameters
    ----------
    mesh : TetMesh
        The part [m].
    material : Material
    n_modes : int
        Elastic modes wanted; a free part also gets its 6 rigid-body modes.
    fix : str or (c,) int, optional
        Nodes clamped in x, y and z: a selection (:func:`~flexarm.fe.select_nodes`,
        e.g. ``"x=min"``) or node indices.  None: a free part.
    backend : str, optional
        Sparse solver (``pardiso``, ``cholmod``, ``splu``).
    matrices : (K, M), optional
        An assembly of ``mesh`` with ``material`` to reuse.
    progress : callable (str) -> None, optional

    Examples
    --------
    >>> from flexarm.fe import MATERIALS
    >>> bar = TetMesh.box((1.0, 0.05, 0.05), (20, 1, 1))
    >>> free = part_modes(bar, MATERIALS["steel"], 2)
    >>> free.n_rigid, len(free.freq_hz)
    (6, 8)
    >>> part_modes(bar, MATERIALS["steel"], 2, fix="x=min").support()
    'clamped 4 nodes (x=min)'
    """
    if n_modes < 1:
        raise ValueError(f"number of modes must be >= 1, got {n_modes}")
    clamped = (np.zeros(0, dtype=np.int64) if fix is None else select_nodes(mesh, fix)
               if isinstance(fix, str) else np.asarray(fix, dtype=np.int64))
    n_free = mesh.n_dofs - 3 * np.unique(clamped).size
    if n_modes > mode_limit(n_free, fix is None):
        raise ValueError(f"n_modes {n_modes}: the part has {n_free} free DOF, at most "
                         f"{mode_limit(n_free, fix is None)} elastic modes")
    say = progress or (lambda message: None)
    say(f"assembling {mesh.n_tets} Tet{4 if mesh.order == 1 else 10} ({mesh.n_dofs} DOF)")
    K, M = matrices if matrices is not None else assemble(mesh, material)
    if fix is None:
        n, solver = n_modes + N_RIGID, shift_invert(None, backend=backend)
    else:
        split = dof_split(mesh.n_dofs, node_dofs(clamped))
        K, M = split.condense(K), split.condense(M)
        n, solver = n_modes, shift_invert(0.0, backend=backend)
    say(f"eigen-solve: {n} modes of {K.shape[0]} DOF")
    result = modes(K, M, n, eigensolver=solver)
    label = fix if isinstance(fix, str) or fix is None else "given nodes"
    return PartModes(result.freq_hz, np.asarray(result.is_rigid), mesh.n_dofs,
                     mass_properties(mesh, material.rho).mass, clamped, label)
