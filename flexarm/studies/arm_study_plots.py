"""Plots of the whole-arm accuracy study (:mod:`flexarm.studies.arm_study`).

``arm_study_error_vs_dof.png`` (log-log error against DOF) and ``arm_study_pareto.png``
(error against build + solve time).  matplotlib is imported inside the functions.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..fe.files import atomic_path
from ..fe.plotting import picture_from_inputs, pyplot
from .arm_study_results import StudyResult

__all__ = ["plot_error_vs_dof", "plot_pareto", "representation_label"]


def representation_label(rep: str, reference_coupling: str) -> str:
    """Legend name of a representation; one that is not the reference's seat coupling
    says so (its difference is a different seat model, not a reduction error)."""
    if rep in ("rbe2", "rbe3") and rep != reference_coupling:
        return f"{rep} (seat model differs from reference {reference_coupling})"
    return rep


def _bottom_row(ax, rows, reps, attr: str, what: str, floor: float, ref_coupling: str) -> None:
    """Error against link FE DOF per representation and mode count; with one mesh only
    (every row at the same DOF), error against CB modes per representation instead."""
    if len({r.n_fe_dofs for r in rows}) > 1:
        for i, (rep, n) in enumerate(dict.fromkeys((r.coupling, r.n_modes) for r in rows)):
            sel = sorted((r for r in rows if r.coupling == rep and r.n_modes == n),
                         key=lambda r: r.n_fe_dofs)
            ax.loglog([r.n_fe_dofs for r in sel],
                      [max(getattr(r, attr), floor) for r in sel], "-", marker="s",
                      color=f"C{reps.index(rep)}", alpha=0.4 + 0.6 * (i % 4) / 3,
                      label=f"{representation_label(rep, ref_coupling)} {sel[0].label}")
        ax.set(xlabel="link FE DOF (3 x nodes)", ylabel=f"largest relative error [-], {what}")
        return
    for i, rep in enumerate(reps):
        sel = sorted((r for r in rows if r.coupling == rep), key=lambda r: r.n_modes)
        ax.semilogy([r.n_modes for r in sel], [max(getattr(r, attr), floor) for r in sel],
                    "-", marker="s", color=f"C{i}", label=representation_label(rep, ref_coupling))
    ax.set(xlabel=f"CB modes per link (0 = Guyan; one mesh: "
                  f"{rows[0].n_fe_dofs} link FE DOF)",
           ylabel=f"largest relative error [-], {what}")


@picture_from_inputs
def plot_error_vs_dof(path, result: StudyResult) -> Path:
    """Log-log PNG: worst frequency / compliance error against reduced DOF (top) and
    against link FE DOF (bottom); one line per mesh and representation (top) or per
    representation and mode count (bottom)."""
    plt = pyplot()
    rows = result.rows
    fig, axes = plt.subplots(2, 2, figsize=(12, 10.5))
    sizes = sorted({r.mesh_size for r in rows}, reverse=True)
    reps = list(dict.fromkeys(r.coupling for r in rows))
    ref_c = result.reference.coupling
    floor = 1e-9
    for col, (attr, what) in enumerate((("freq_err_max", "first frequencies"),
                                        ("C_err_max", "TCP compliance diagonal"))):
        ax = axes[0, col]
        for j, h in enumerate(sizes):
            for i, rep in enumerate(reps):
                sel = sorted((r for r in rows if r.mesh_size == h and r.coupling == rep),
                             key=lambda r: r.n_reduced)
                if sel:
                    ax.loglog([r.n_reduced for r in sel],
                              [max(getattr(r, attr), floor) for r in sel],
                              ["-", "--", "-.", ":"][j % 4], marker="o", color=f"C{i}",
                              label=f"{representation_label(rep, ref_c)}, {h * 1e3:.0f} mm")
        ax.set(xlabel="reduced arm DOF",
               ylabel=f"largest relative error [-], {what} (floor 1e-9)")
        _bottom_row(axes[1, col], rows, reps, attr, what, floor, ref_c)
    from matplotlib.ticker import NullFormatter

    _mesh_error_lines(axes[:, 0], result)
    for ax in axes.ravel():
        ax.xaxis.set_minor_formatter(NullFormatter())  # narrow log ranges: no clutter
        ax.axhline(0.01, color="grey", lw=0.8, ls=":")
        ax.axhline(0.001, color="grey", lw=0.8, ls=":")
        ax.grid(True, which="both", alpha=0.3)
        # below the axes: inside, "best" still hid the last (most accurate) points
        ax.legend(fontsize=7, ncol=2, loc="upper center", bbox_to_anchor=(0.5, -0.13),
                  frameon=False)
    ref = result.reference
    fig.suptitle(f"Arm accuracy at {result.pose}: {_variants(rows)} vs full FE "
                 f"({ref.n_dofs} DOF, {ref.mesh_size * 1e3:.0f} mm, {ref.coupling})")
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)
    return Path(path)


def _variants(rows) -> str:
    """``"Guyan and CB(5, 10)"``: the reduced models the study compared."""
    cb = sorted({r.n_modes for r in rows if r.n_modes})
    names = (["Guyan"] if any(r.n_modes == 0 for r in rows) else []) + (
        [f"CB({', '.join(map(str, cb))})"] if cb else [])
    return " and ".join(names)


def _mesh_error_lines(axes, result: StudyResult) -> None:
    """The estimated discretisation error of the frequencies as horizontal lines: the
    reduction errors below them are smaller than what the mesh already costs."""
    est = result.discretisation
    if est is None:
        return
    for ax in axes:
        if est.lower is not None:
            ax.axhline(est.lower, color="firebrick", lw=1.2, ls="--",
                       label=f"mesh error, at least (vs Tet10, mode {est.worst_mode})")
        if est.richardson is not None:
            ax.axhline(est.richardson, color="darkorange", lw=1.2, ls="-.",
                       label="mesh error, Richardson estimate")


@picture_from_inputs
def plot_pareto(path, result: StudyResult) -> Path:
    """PNG: worst error against build + solve time, Pareto front drawn as a step line."""
    plt = pyplot()
    rows = sorted(result.rows, key=lambda r: (r.seconds, r.error))
    fig, ax = plt.subplots(figsize=(9, 6))
    reps = list(dict.fromkeys(r.coupling for r in result.rows))
    floor = 1e-9
    for i, rep in enumerate(reps):
        sel = [r for r in rows if r.coupling == rep]
        ax.loglog([max(r.seconds, 1e-4) for r in sel], [max(r.error, floor) for r in sel], "o",
                  color=f"C{i}", label=representation_label(rep, result.reference.coupling))
    front, best = [], np.inf
    for r in rows:
        if r.error < best * (1 - 1e-6):  # strictly better (ties are not on the front)
            best = r.error
            front.append(r)
    ax.step([max(r.seconds, 1e-4) for r in front], [max(r.error, floor) for r in front], "k-",
            where="post", lw=1, label="Pareto front")
    for r in front:
        ax.annotate(f"{r.label} {r.coupling} {r.mesh_size * 1e3:.0f} mm", (max(r.seconds, 1e-4),
                    max(r.error, floor)), fontsize=7, xytext=(4, 4), textcoords="offset points")
    ax.axhline(0.01, color="grey", lw=0.8, ls=":")
    ax.axhline(0.001, color="grey", lw=0.8, ls=":")
    ax.set(xscale="log", yscale="log", xlabel="build + solve time [s]",
           ylabel="max(frequency error, compliance error) [-]",
           title=f"Arm study at {result.pose}: {_variants(result.rows)} vs full FE, "
                 "accuracy against cost")
    from matplotlib.ticker import FormatStrFormatter

    # build times span well under a decade: plain numbers on the minor ticks, not 2x10^0
    ax.xaxis.set_major_formatter(FormatStrFormatter("%g"))
    ax.xaxis.set_minor_formatter(FormatStrFormatter("%g"))
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)
    return Path(path)
