"""Predictions vs measurements: error tables like thesis Table 5, chi^2_red, plots.

Error per series (thesis eqs. 4.1-4.2): the absolute error is the mean over the
loaded readings of ``|d_meas - d_pred|`` along the load direction; the relative error
divides by the mean ``|d_meas|``.  The table groups series by pose and load direction.
chi^2_red uses the GLS noise model of :mod:`flexarm.validation.static.fit` with the *stated*
noise (no fitted parameters: dof = number of observations).
"""

from __future__ import annotations

import csv
from dataclasses import dataclass, fields
from pathlib import Path

import numpy as np

from ...assembly.system import ArmModel
from ...fe.plotting import pyplot
from ...fe.text import text_table
from ..data.measurements import StaticData
from ..tolerances import tol
from .fit import Problem, chi2_band
from .plots import plot_residual_vs_torque, write_residuals

__all__ = ["SeriesError", "Comparison", "compare_static", "write_report", "write_rows"]


@dataclass(frozen=True)
class SeriesError:
    """Error of the model on one load series (a row of ``errors.csv``).

    Attributes
    ----------
    series : str
        Series label, ``"<pose>_<dir>"``.
    pose : str
        Pose label.
    dir : str
        Load direction, ``"+x"`` ... ``"-z"`` (the force component that dominates).
    mean_abs_mm, max_abs_mm : float
        Mean and largest ``|d_meas - d_pred|`` along the load direction over the loaded
        readings [mm].
    relative : float
        ``mean_abs_mm`` over the mean ``|d_meas|`` along the load direction
        (dimensionless).
    max_meas_mm : float
        Largest measured ``|d_meas|`` along the load direction [mm].
    """

    series: str
    pose: str
    dir: str
    mean_abs_mm: float
    max_abs_mm: float
    relative: float
    max_meas_mm: float


@dataclass(frozen=True)
class Comparison:
    """Result of :func:`compare_static`.

    Attributes
    ----------
    predicted : (n, 3) float
        Predicted relative deflections [m].
    table : tuple of SeriesError
        One row per series, in the order of the data.
    chi2_red : float
        GLS chi^2 per observation with the stated noise.
    band : (float, float)
        Acceptance band of ``chi2_red``.
    rms : float
        RMS of ``d_meas - d_pred`` over loaded readings [m].
    problem : Problem
        The data with the noise model and kinematics the comparison used.
    model : str
        Which model was compared (``"E-model"``, or ``"flexible model"`` with the
        links' flexibility), for titles.
    """

    predicted: np.ndarray
    table: tuple[SeriesError, ...]
    chi2_red: float
    band: tuple
    rms: float
    problem: Problem
    model: str = "E-model"

    @property
    def poses(self) -> str:
        """The measured poses, e.g. ``"P1, P2, P3"``."""
        return ", ".join(sorted({r.pose for r in self.table}))

    def text(self) -> str:
        """The error table [mm], chi2_red with its band and the RMS [µm], as ``compare``
        prints them."""
        lo, hi = self.band
        return "\n".join([
            text_table(["series", "mean_abs_mm", "max_abs_mm", "relative", "max_meas_mm"],
                       [[r.series, r.mean_abs_mm, r.max_abs_mm, r.relative, r.max_meas_mm]
                        for r in self.table], "{:.4f}"),
            f"chi2_red = {self.chi2_red:.3f} (band {lo:.3f}-{hi:.3f} for the stated noise), "
            f"RMS = {self.rms * 1e6:.1f} µm"])

    def write(self, folder) -> list[Path]:
        """:func:`write_report` into ``folder``."""
        return write_report(folder, self)


def compare_static(arm: ArmModel, data: StaticData, effects=(),
                   sigma: float = tol.tracker_sigma, flexible: ArmModel | None = None
                   ) -> Comparison:
    """Compare ``arm`` (plus ``effects``) with static ``data``.

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> import numpy as np
    >>> d = StaticData(series=["a"] * 3, steps=[0, 1, 2], q=np.zeros((3, 6)),
    ...                force=np.zeros((3, 3)), disp=np.zeros((3, 3)))
    """
    pb = Problem(arm, data, sigma, flexible=flexible)
    pred = pb.predict(list(effects))
    r = pb.whiten(data.disp - pred)
    chi2_red = float(r @ r / max(pb.n_obs, 1))
    rows = []
    for g in pb.groups:
        loaded = g[1:]
        f = data.force[loaded]
        k = int(np.argmax(np.abs(f).sum(axis=0))) if loaded.size else 0
        sgn = np.sign(f[:, k].sum()) or 1.0
        err = np.abs(data.disp[loaded, k] - pred[loaded, k])
        meas = np.abs(data.disp[loaded, k])
        label = str(data.series[g[0]])
        rows.append(SeriesError(
            series=label, pose=label.split("_")[0], dir=("-" if sgn < 0 else "+") + "xyz"[k],
            mean_abs_mm=float(err.mean() * 1e3) if err.size else 0.0,
            max_abs_mm=float(err.max() * 1e3) if err.size else 0.0,
            relative=float(err.mean() / max(meas.mean(), 1e-12)) if err.size else 0.0,
            max_meas_mm=float(meas.max() * 1e3) if err.size else 0.0))
    res = (data.disp - pred)[~pb.is_ref]
    return Comparison(pred, tuple(rows), chi2_red, chi2_band(max(pb.n_obs, 1)),
                      float(np.sqrt(np.mean(res**2))) if res.size else 0.0, pb,
                      "E-model" if flexible is None else "flexible model")


def write_rows(path, row_type: type, rows) -> None:
    """Write the dataclass ``rows`` (instances of ``row_type``) as CSV: one column per
    field, in field order; values as :mod:`csv` writes them (``repr`` of floats)."""
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow([f.name for f in fields(row_type)])
        w.writerows([getattr(r, f.name) for f in fields(row_type)] for r in rows)


def write_report(folder, cmp: Comparison) -> list[Path]:
    """Write ``errors.csv`` and the plots (matplotlib, Agg) into ``folder``."""
    plt = pyplot()

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    out = [folder / "errors.csv"]
    write_rows(out[0], SeriesError, cmp.table)
    pb, data = cmp.problem, cmp.problem.data
    fmag = np.linalg.norm(data.force, axis=1)
    n = len(pb.groups)
    cols = min(n, 6)
    rows = -(-n // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(3 * cols, 2.4 * rows), squeeze=False)
    for ax, g in zip(axes.ravel(), pb.groups, strict=False):
        for k, c in enumerate("xyz"):
            ax.plot(fmag[g], data.disp[g, k] * 1e3, "o", ms=3, color=f"C{k}", label=f"{c} meas")
            ax.plot(fmag[g], cmp.predicted[g, k] * 1e3, "-", color=f"C{k}")
        ax.set_title(str(data.series[g[0]]), fontsize=8)
        ax.tick_params(labelsize=7)
    fig.supylabel("deflection [mm]", fontsize=8)
    axes[0, 0].legend(fontsize=6)
    fig.supxlabel("load |F| [N]  (points: measured, lines: model)", fontsize=8)
    fig.suptitle(f"TCP deflection, measured vs {cmp.model}, at {cmp.poses}", fontsize=9)
    # Fixed margins: tight_layout over dozens of panels costs seconds per figure.
    fig.subplots_adjust(left=0.06, right=0.99, bottom=0.4 / rows, top=1 - 0.25 / rows,
                        wspace=0.35, hspace=0.45)
    out.append(folder / "deflection_vs_force.png")
    fig.savefig(out[-1], dpi=90)
    plt.close(fig)
    res = (data.disp - cmp.predicted) * 1e6
    out += [write_residuals(folder / "residuals.csv", data.series, pb.tau, res * 1e-6,
                            data.force, data.disp, cmp.predicted),
            plot_residual_vs_torque(folder / "residual_vs_torque.png", pb.tau, res * 1e-6,
                                    f"{cmp.model} at {cmp.poses}")]
    poses = sorted({r.pose for r in cmp.table})
    fig, ax = plt.subplots(figsize=(5, 3))
    pose_of = np.array([str(s).split("_")[0] for s in data.series])
    ax.boxplot([np.abs(res[(pose_of == p) & ~pb.is_ref]).ravel() for p in poses])
    ax.set_xticks(np.arange(1, len(poses) + 1), poses)
    ax.set_ylabel("|residual| [µm]")
    ax.set_xlabel("pose")
    ax.set_title(f"|measured - {cmp.model}| at {cmp.poses}", fontsize=9)
    fig.tight_layout()
    out.append(folder / "residual_by_pose.png")
    fig.savefig(out[-1], dpi=90)
    plt.close(fig)
    return out
