"""Single-link accuracy study: how good is a superelement, and what does it cost?

For each mesh, interface representation and Craig-Bampton mode count, the reduced
model is compared with the unreduced FE model of the same part *with the same
coupling and supports* (interface ``a`` clamped):

* relative error of the first ``n_freq`` frequencies of the clamped-free link;
* relative error (Frobenius) of the static compliance at each interface with the
  other interface clamped.

Results go to a CSV and a log-log PNG (error against reduced DOF count, reduction
time on a second axis).
"""

from __future__ import annotations

import csv
import logging
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import scipy.linalg as sla

from ..fe.boundary import dof_split
from ..fe.eigen import modes, shift_invert, static_solve
from ..fe.files import atomic_path
from ..fe.material import Material
from ..fe.mesh import TetMesh
from ..fe.plotting import pyplot
from ..fe.text import text_table
from ..reduction.craig_bampton import craig_bampton
from ..reduction.interfaces import CylinderRegion
from ..reduction.reduce import CoupledModel, coupled_model

__all__ = ["StudyRow", "PartStudyResult", "REPRESENTATIONS", "bar_link", "study_part",
           "run_part_study", "write_csv", "plot_study"]

log = logging.getLogger(__name__)

#: label -> (coupling kind, masters per region or None for all)
REPRESENTATIONS = {"rbe2": ("rbe2", None), "rbe3": ("rbe3", None), "k4": ("nodes", 4),
                   "k8": ("nodes", 8), "k16": ("nodes", 16), "all": ("nodes", None)}


@dataclass(frozen=True)
class StudyRow:
    """One reduced model of the study (errors are relative, times in seconds)."""

    mesh: str
    n_full: int
    representation: str
    n_modes: int
    n_reduced: int
    freq_error: float
    n_freq: int
    compliance_error: float
    reduce_seconds: float
    full_seconds: float


def bar_link(length: float = 0.6, width: float = 0.06, divisions=(8, 1, 1), order: int = 1):
    """A box bar along x with disc interfaces ``a`` (x = 0) and ``b`` (x = length).

    >>> mesh, regions = bar_link(divisions=(4, 1, 1))
    >>> mesh.n_nodes, [r.name for r in regions]
    (20, ['a', 'b'])
    """
    mesh = TetMesh.box((length, width, width), divisions, order=order)
    c = width / 2
    eps = 1e-6 * length
    regions = [CylinderRegion("a", (0.0, c, c), (1, 0, 0), 0.0, width, eps),
               CylinderRegion("b", (length, c, c), (1, 0, 0), 0.0, width, eps)]
    return mesh, regions


def _owner_dofs(model: CoupledModel, interface: int, offset: int) -> np.ndarray:
    c = model.coupling
    return offset + np.flatnonzero(np.repeat(c.node_interface, c.dofs_per_node) == interface)


def _full_reference(model: CoupledModel, n_freq: int):
    """Clamped-free frequencies and the interface compliances of the coupled FE model."""
    n = model.K.shape[0]
    n_i = model.coupling.n_interior
    split = dof_split(n, _owner_dofs(model, 0, n_i))
    K, M = split.condense(model.K), split.condense(model.M)
    w = modes(K, M, min(n_freq, K.shape[0] - 2), eigensolver=shift_invert(0.0)).omega2
    compl = []
    for load, clamp in ((1, 0), (0, 1)):
        dl = _owner_dofs(model, load, n_i)
        F = np.zeros((n, dl.size))
        F[dl, np.arange(dl.size)] = 1.0
        compl.append(static_solve(model.K, F, dof_split(n, _owner_dofs(model, clamp, n_i)))[dl])
    return w, compl


def _reduced_errors(model: CoupledModel, K_r, M_r, ref_w, ref_c):
    nb_nodes = model.coupling.node_interface
    dpn = model.coupling.dofs_per_node
    owner = np.repeat(nb_nodes, dpn)
    owner = np.concatenate([owner, np.full(K_r.shape[0] - owner.size, -1)])
    free = np.flatnonzero(owner != 0)
    k = min(len(ref_w), free.size)
    w = sla.eigh(K_r[np.ix_(free, free)], M_r[np.ix_(free, free)], eigvals_only=True,
                 subset_by_index=(0, k - 1))
    f_err = float(np.max(np.abs(np.sqrt(w / ref_w[:k]) - 1)))
    c_err = 0.0
    for (load, clamp), C in zip(((1, 0), (0, 1)), ref_c, strict=True):
        keep = np.flatnonzero(owner != clamp)
        C_r = np.linalg.inv(K_r[np.ix_(keep, keep)])
        dl = np.searchsorted(keep, np.flatnonzero(owner == load))
        c_err = max(c_err, float(np.linalg.norm(C_r[np.ix_(dl, dl)] - C) / np.linalg.norm(C)))
    return f_err, k, c_err


def study_part(material: Material, meshes=None, representations=tuple(REPRESENTATIONS),
               mode_counts=(0, 5, 10, 20, 40), n_freq: int = 10) -> list[StudyRow]:
    """Run the sweep.

    Parameters
    ----------
    material : Material
    meshes : sequence of (label, TetMesh, regions), optional
        Two interfaces each (the first is clamped).  Default: two Tet4 bars.
    representations : sequence of str
        Keys of :data:`REPRESENTATIONS`.
    mode_counts : sequence of int
        Craig-Bampton modes (0 = Guyan); clipped to the interior DOF count.
    """
    if meshes is None:
        meshes = [(f"bar {d[0]}x{d[1]}x{d[2]}", *bar_link(divisions=d))
                  for d in ((12, 2, 2), (24, 3, 3))]
    unknown = [r for r in representations if r not in REPRESENTATIONS]
    if unknown:
        raise ValueError(f"representation must be among {', '.join(REPRESENTATIONS)}, "
                         f"got '{unknown[0]}'")
    rows = []
    for label, mesh, regions in meshes:
        from ..fe.assembly import assemble

        KM = assemble(mesh, material)
        for rep in representations:
            kind, k = REPRESENTATIONS[rep]
            model = coupled_model(mesh, material, regions, kind, k, matrices=KM)
            t0 = time.perf_counter()
            ref_w, ref_c = _full_reference(model, n_freq)
            t_full = time.perf_counter() - t0
            done = set()
            for n in mode_counts:
                n = min(int(n), model.coupling.n_interior)
                if n in done:
                    continue
                done.add(n)
                t0 = time.perf_counter()
                red = craig_bampton(model.K, model.M, model.coupling.n_boundary, n)
                dt = time.perf_counter() - t0
                f_err, k_f, c_err = _reduced_errors(model, red.K, red.M, ref_w, ref_c)
                rows.append(StudyRow(label, mesh.n_dofs, rep, n, red.K.shape[0], f_err, k_f,
                                     c_err, dt, t_full))
            log.info("study: %s %s done", label, rep)
    return rows


def write_csv(path, rows: list[StudyRow]) -> Path:
    """Write the rows as CSV (header = :class:`StudyRow` fields) atomically."""
    with atomic_path(path) as tmp, open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(StudyRow.__dataclass_fields__))
        w.writeheader()
        for r in rows:
            w.writerow(asdict(r))
    return Path(path)


def plot_study(path, rows: list[StudyRow]) -> Path:
    """Log-log PNG: frequency error vs reduced DOF per mesh/representation; time on the
    right axis (dotted)."""
    plt = pyplot()

    fig, ax = plt.subplots(figsize=(9, 6))
    tax = ax.twinx()
    meshes = list(dict.fromkeys(r.mesh for r in rows))
    styles = ["-", "--", "-.", ":"]
    for j, m in enumerate(meshes):
        for i, rep in enumerate(dict.fromkeys(r.representation for r in rows)):
            sel = sorted((r for r in rows if r.mesh == m and r.representation == rep),
                         key=lambda r: r.n_reduced)
            if not sel:
                continue
            x = [r.n_reduced for r in sel]
            err = [max(r.freq_error, 1e-16) for r in sel]
            color = f"C{i}"
            ax.loglog(x, err, styles[j % 4], marker="o", color=color, label=f"{rep}, {m}")
            tax.loglog(x, [r.reduce_seconds for r in sel], ":", marker="x", color=color,
                       alpha=0.5)
    ax.set_xlabel("reduced DOF")
    ax.set_ylabel("largest relative error, first frequencies (clamped-free)")
    tax.set_ylabel("reduction time [s] (dotted)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    ax.set_title("Single-link accuracy: Craig-Bampton modes and interface representation")
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=120, format="png")
    plt.close(fig)
    return Path(path)


@dataclass(frozen=True)
class PartStudyResult:
    """The rows of a part study and the files written (``study.csv``, ``study.png``)."""

    rows: tuple[StudyRow, ...]
    files: tuple[Path, ...] = ()

    def text(self) -> str:
        """One table row per mesh, representation and mode count."""
        return text_table(["mesh", "repr", "modes", "DOF", "freq err", "compl err", "time [s]"],
                          [[r.mesh, r.representation, r.n_modes, r.n_reduced, r.freq_error,
                            r.compliance_error, r.reduce_seconds] for r in self.rows], "{:.3g}")


def run_part_study(material: Material, representations=tuple(REPRESENTATIONS),
                   mode_counts=(0, 5, 10, 20, 40), divisions=((12, 2, 2), (24, 3, 3)),
                   mesh=None, out_dir=None) -> PartStudyResult:
    """:func:`study_part` on built-in bars of ``divisions`` (cells along x, y, z) or on one
    ``mesh`` = ``(label, TetMesh, two regions)``; with ``out_dir``, writes ``study.csv``
    and ``study.png`` there.

    Examples
    --------
    >>> from flexarm.fe import MATERIALS
    >>> res = run_part_study(MATERIALS["steel"], ("rbe2",), (0, 5), divisions=((6, 1, 1),))
    >>> [r.n_modes for r in res.rows]
    [0, 5]
    """
    meshes = ([mesh] if mesh is not None else
              [(f"bar {d[0]}x{d[1]}x{d[2]}", *bar_link(divisions=tuple(d))) for d in divisions])
    rows = tuple(study_part(material, meshes, tuple(representations), tuple(mode_counts)))
    files: tuple[Path, ...] = ()
    if out_dir is not None:
        files = (write_csv(Path(out_dir) / "study.csv", list(rows)),
                 plot_study(Path(out_dir) / "study.png", list(rows)))
    return PartStudyResult(rows, files)
