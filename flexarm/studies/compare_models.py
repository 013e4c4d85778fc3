"""Side-by-side comparison of arm models at poses: E-model, Guyan, CB(n), CB + coupled
wrist and the full-FE reference (first frequencies, TCP compliance diagonal, Bode).

"Rigid-body" in the sense *rigid links and rigid joints* has no modes and no
compliance, so it is not a column; the rigid-*link* model is the E-model.  Every
difference between the E-model and the flexible models is link flexibility, because
they share kinematics, joints, base, tool and mass properties.
"""

from __future__ import annotations

import csv
import logging
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..assembly.analyses import frf, modes, tcp_compliance
from ..assembly.build import BuildOptions, Mesher, build_robot
from ..assembly.emodel import emodel
from ..assembly.flexible import flexible_arm
from ..assembly.full_fe import full_fe_analysis, full_fe_bodies
from ..fe.files import atomic_path, writes_folder
from ..fe.plotting import picture_from_inputs, pyplot
from ..fe.typing import FloatArray
from ..robot.description import Robot, pose_from_string
from ..validation.dynamic.mac import mac, pair_modes

__all__ = ["ModelResult", "ComparisonReport", "compare_models", "paired_reference"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class ModelResult:
    """One model at one pose: ``freq_hz`` (n,) [Hz], ``C_diag`` (6,) TCP compliance
    diagonal [m/N, rad/(N m)], ``n_dofs``, the Y receptance magnitude ``bode``
    (nf,) [m/N] at the report's ``freq_hz`` (None for the full-FE reference) and the
    TCP motion of each mode ``tcp_shapes`` (6, n) [m, rad] (None: modes are paired by
    index)."""

    model: str
    pose: str
    freq_hz: FloatArray
    C_diag: FloatArray
    n_dofs: int
    bode: FloatArray | None = None
    tcp_shapes: FloatArray | None = None


def paired_reference(result: ModelResult, ref: ModelResult) -> np.ndarray:
    """(n,) index of the reference mode paired with each mode of ``result`` (-1: none).

    Paired by the MAC of their TCP motion (one-to-one, MAC >= 0.8, frequencies within a
    factor 2: :func:`~flexarm.validation.dynamic.mac.pair_modes`); by index when either
    lacks shapes.  A rigid-link model has fewer modes than a flexible one and its
    higher modes are other motions than the reference's of the same rank: pairing by
    rank would compare a wrist mode with a link-bending one.

    Examples
    --------
    >>> a = ModelResult("E", "P1", np.array([10.0, 50.0]), np.ones(6), 6,
    ...                 tcp_shapes=np.array([[1.0, 0], [0, 1], [0, 0], [0, 0], [0, 0], [0, 0]]))
    >>> b = ModelResult("FE", "P1", np.array([9.9, 30.0, 52.0]), np.ones(6), 900,
    ...                 tcp_shapes=np.array([[1.0, 0, 0], [0, 0, 1], [0, 1, 0],
    ...                                      [0, 0, 0], [0, 0, 0], [0, 0, 0]]))
    >>> paired_reference(a, b).tolist()
    [0, 2]
    """
    n = len(result.freq_hz)
    if result.tcp_shapes is None or ref.tcp_shapes is None:
        k = np.arange(n)
        return np.where(k < len(ref.freq_hz), k, -1)
    M = mac(np.asarray(result.tcp_shapes).T, np.asarray(ref.tcp_shapes).T)
    return pair_modes(M, result.freq_hz, ref.freq_hz).model


@dataclass(frozen=True)
class ComparisonReport:
    """All results, the reference model's name and the written files."""

    results: tuple[ModelResult, ...]
    reference: str
    bode_freq_hz: FloatArray
    files: tuple[Path, ...] = field(default=())

    def get(self, model: str, pose: str) -> ModelResult:
        for r in self.results:
            if r.model == model and r.pose == pose:
                return r
        raise KeyError(f"no result for model '{model}' at pose '{pose}'")

    def rows(self) -> list[dict]:
        """Table rows: frequencies [Hz], compliance [mm/kN] and errors [%] vs reference."""
        out = []
        for r in self.results:
            ref = self.get(self.reference, r.pose)
            pairs = paired_reference(r, ref)
            mine = np.flatnonzero(pairs >= 0)
            d = {"pose": r.pose, "model": r.model, "n_dofs": r.n_dofs}
            for k in range(len(r.freq_hz)):
                d[f"f{k + 1}_Hz"] = float(r.freq_hz[k])
            for a, name in enumerate("xyz"):
                d[f"C{name}{name}_mm_per_kN"] = float(r.C_diag[a] * 1e6)
            err_f = 100 * (r.freq_hz[mine] / ref.freq_hz[pairs[mine]] - 1)
            err_c = 100 * (r.C_diag[:3] / ref.C_diag[:3] - 1)
            d["max_f_err_pct"] = float(np.abs(err_f).max()) if mine.size else float("nan")
            d["max_C_err_pct"] = float(np.abs(err_c).max())
            out.append(d)
        return out

    def text(self) -> str:
        """A plain-text table of :meth:`rows`."""
        lines = []
        for d in self.rows():
            fs = " ".join(f"{d[k]:7.2f}" for k in d if k.endswith("_Hz"))
            lines.append(f"{d['pose']:>4} {d['model']:<18} {d['n_dofs']:>7} | {fs} | C mm/kN "
                         f"{d['Cxx_mm_per_kN']:.4f} {d['Cyy_mm_per_kN']:.4f} "
                         f"{d['Czz_mm_per_kN']:.4f} | err f {d['max_f_err_pct']:.3f}% "
                         f"C {d['max_C_err_pct']:.3f}%")
        return "\n".join(lines)

    def write(self, out) -> ComparisonReport:
        """This report with its files written into folder ``out``:
        ``model_comparison.csv``, ``model_comparison_bode.csv`` and
        ``model_comparison_bode.png`` (poses in the order of :attr:`results`)."""
        poses = list(dict.fromkeys(r.pose for r in self.results))
        files = _write(self, Path(out), poses)
        return ComparisonReport(self.results, self.reference, self.bode_freq_hz, files)


@writes_folder("out")
def _write(report: ComparisonReport, out: Path, poses: list[str]) -> tuple[Path, ...]:
    """``model_comparison.csv`` (:meth:`ComparisonReport.rows`), the Bode magnitudes
    behind the plot in ``model_comparison_bode.csv`` (pose, model, ``freq_Hz``,
    ``abs_Hyy_m_per_N``; SI) and ``model_comparison_bode.png`` (drawn in
    :data:`~flexarm.studies.plots.RECEPTANCE_UNIT`)."""
    out.mkdir(parents=True, exist_ok=True)
    rows = report.rows()
    keys = list(dict.fromkeys(k for r in rows for k in r))
    path = out / "model_comparison.csv"
    with atomic_path(path) as tmp, tmp.open("w", newline="") as fh:
        w = csv.DictWriter(fh, keys)
        w.writeheader()
        w.writerows(rows)
    curves = [r for pose in poses for r in report.results if r.pose == pose and r.bode is not None]
    bode_csv = out / "model_comparison_bode.csv"
    with atomic_path(bode_csv) as tmp, tmp.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["pose", "model", "freq_Hz", "abs_Hyy_m_per_N"])
        w.writerows([r.pose, r.model, f"{f:.10g}", f"{h:.10g}"]
                    for r in curves for f, h in zip(report.bode_freq_hz, r.bode, strict=True))
    bode = [(r.pose, r.model, r.bode) for r in curves]
    png = _bode_png(out / "model_comparison_bode.png", poses, report.bode_freq_hz, bode)
    return path, bode_csv, png


@picture_from_inputs
def _bode_png(path, poses: list[str], freq_hz, curves: list[tuple]) -> Path:
    """``model_comparison_bode.png``: one panel per pose of ``|H_yy|`` of each
    ``(pose, model, |H_yy| [m/N])`` curve."""
    from .plots import RECEPTANCE_SCALE, RECEPTANCE_UNIT

    plt = pyplot()
    fig, axes = plt.subplots(1, len(poses), figsize=(5 * len(poses), 4), squeeze=False)
    for ax, pose in zip(axes[0], poses, strict=True):
        for at, model, h in curves:
            if at == pose:
                ax.loglog(freq_hz, h * RECEPTANCE_SCALE, label=model)
        ax.set(title=f"{pose}: TCP receptance Y/Y", xlabel="frequency [Hz]",
               ylabel=f"|H_yy| [{RECEPTANCE_UNIT}]")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    models = list(dict.fromkeys(model for _, model, _ in curves))
    fig.suptitle("TCP receptance: " + " vs ".join(models), fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return Path(path)


def compare_models(
    robot: Robot,
    poses=("P1", "P2", "P3"),
    n_modes: int | None = None,
    coupling: str = "rbe2",
    mesh_size: float | None = None,
    n_freq: int = 10,
    full_fe: bool = True,
    mass_method: str = "tets",
    out_dir=None,
    mesher: Mesher | None = None,
    bode_freq_hz: FloatArray | None = None,
    progress: Callable[[str], None] | None = None,
) -> ComparisonReport:
    """Compare E-model, Guyan, CB(n), CB + coupled wrist and full FE at ``poses``.

    When the robot has equivalent E-model joints, the bearing-only E-model is shown too:
    it is the flexible models' assembly with rigid links, so its difference from CB is
    link flexibility alone.

    Parameters
    ----------
    robot : Robot
    poses : sequence of str
        Pose names or ``"q1,...,qn"`` in degrees.
    n_modes, coupling, mesh_size
        Build options (None: the robot's defaults).
    n_freq : int
        Frequencies compared per model.
    full_fe : bool
        Include the full-FE reference (else CB is the reference).
    mass_method : {"tets", "surface"}
        E-model mass properties (``"tets"`` = the same solids as the superelements).
    out_dir : path, optional
        Write ``model_comparison.csv``, ``model_comparison_bode.csv`` and
        ``model_comparison_bode.png`` there.
    mesher, progress
        As for :func:`~flexarm.assembly.build.build_robot`.
    """
    say = progress or (lambda message: None)
    cb = BuildOptions("cb", n_modes, coupling, mesh_size).resolved(robot)
    gy = BuildOptions("guyan", 0, coupling, mesh_size).resolved(robot)
    say("building Craig-Bampton links")
    b_cb = build_robot(robot, cb, mesher=mesher, progress=say)
    say("building Guyan links")
    b_gy = build_robot(robot, gy, mesher=mesher, progress=say)
    # Two E-models: with the equivalent joints (bearing in series with link bending, the
    # lumped model a user identifies) and with the bearing-only joints of the flexible
    # models, so "E-model (bearing)" vs CB differs by link flexibility alone.
    models = {"E-model": emodel(robot, mass_method, cb.mesh_size)}
    if any(j.emodel is not None for j in robot.joints):
        models["E-model (bearing)"] = emodel(robot, mass_method, cb.mesh_size, equivalent=False)
    models.update({"Guyan": flexible_arm(robot, gy, b_gy), cb.label: flexible_arm(robot, cb, b_cb)})
    # a robot without [wrist] would get a row identical to CB's
    if robot.chain.n_joints >= 6 and (robot.wrist_coupling is not None
                                      or robot.wrist_stiffness is not None):
        models[f"{cb.label}+wrist"] = flexible_arm(robot, cb, b_cb, coupled_wrist=True)
    fb = full_fe_bodies(robot, cb, mesher, say) if full_fe else None
    fbode = np.geomspace(1, 1000, 300) if bode_freq_hz is None else np.asarray(bode_freq_hz)
    results = []
    for pname in poses:
        q = pose_from_string(robot, pname)
        for name, arm in models.items():
            say(f"{pname}: {name}")
            md = modes(arm, q)
            C = np.diag(tcp_compliance(arm, q))
            H = np.abs(frf(arm, q, fbode)[:, 1, 1])
            results.append(ModelResult(name, pname, md.freq_hz[:n_freq], C, arm.layout["n"],
                                       H, md.tcp_shapes[:, :n_freq]))
        if fb is not None:
            say(f"{pname}: full FE")
            ref = full_fe_analysis(models[cb.label], fb, q, n_freq)
            results.append(ModelResult("full-FE", pname, ref.freq_hz, np.diag(ref.C),
                                       ref.n_dofs, tcp_shapes=ref.tcp_shapes))
    report = ComparisonReport(tuple(results), "full-FE" if full_fe else cb.label, fbode)
    return report if out_dir is None else report.write(out_dir)
