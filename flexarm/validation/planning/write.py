"""A test plan as a RAPID module (moves to each pose) and as a plot of its expected ΔBIC."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...robot.formats.rapid import (
    EXTAX_UNUSED,
    JointTarget,
    Motion,
    Procedure,
    RapidModule,
    write_rapid,
)

__all__ = ["plan_module", "write_module", "plot_expected"]


def plan_module(plan, name: str = "FlexarmTestPlan") -> RapidModule:
    """RAPID module of ``plan``: a joint target per series (axes [deg], the robot file's
    joint angles), a ``PROC`` per series moving there (``MoveAbsJ``, ``fine``) and
    ``main`` visiting them in order, as the thesis's measurement program does between
    load series."""
    extax = [float(EXTAX_UNUSED)] * 6
    targets, procs, main = {}, {}, []
    for s in plan.series:
        jt = JointTarget(f"j{s.label}", np.degrees(s.q), extax)
        targets[jt.name] = jt
        move = Motion("MoveAbsJ", (jt,), "v100", "fine", "tool0", None, (), 0)
        procs[f"Series_{s.label}"] = Procedure(f"Series_{s.label}", (move,), 0)
        main.append(move)
    return RapidModule(name, {}, {"main": Procedure("main", tuple(main), 0), **procs},
                       joint_targets=targets)


def write_module(path, plan) -> Path:
    """Write :func:`plan_module` to ``path`` (atomic); returns the path."""
    write_rapid(path, plan_module(plan))
    return Path(path)


def plot_expected(path, plan) -> Path:
    """Bar chart: smallest expected ΔBIC over hypothesis pairs after each chosen series,
    with the acceptance line ΔBIC = 10."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 3.5))
    labels = [f"{s.label}\n{s.direction}" for s in plan.series]
    ax.bar(labels, [s.expected for s in plan.series], color="tab:blue")
    ax.axhline(10.0, color="tab:red", ls="--", label="ΔBIC = 10")
    ax.set_ylabel("expected min ΔBIC after series")
    ax.set_title(" vs ".join(h.spec for h in plan.hypotheses), fontsize=9)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return Path(path)
