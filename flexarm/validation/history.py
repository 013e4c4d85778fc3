"""Model versions: write the updated robot file, the error history and its plot.

Linear effects go into the robot TOML through the standard writer (torsion, tilt,
foundation spring, wrist stiffness; link flexibility ``c`` as the links' Young's
modulus ``E / c``, used by the flexible model).  Nonlinear joint laws go into an optional
top-level ``[nonlinear.<joint name>]`` table that the core reader ignores and
:func:`read_robot_effects` reads back (keys: ``backlash_rad``; ``hardening_extra_rad_per_Nm``
+ ``hardening_threshold_Nm``; ``hysteresis_lost_rad`` + ``hysteresis_radius_Nm``).
"""

from __future__ import annotations

import csv
import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import tomllib

from ..assembly.robot import BaseSupport, Robot
from ..assembly.system import ArmModel
from ..fe.files import atomic_path
from ..fe.plotting import pyplot
from .effects import Effect, apply_effects, resolve

__all__ = ["robot_with_effects", "write_robot", "read_robot_effects", "write_history"]

_NONLINEAR = ("backlash", "hardening", "hysteresis")


def _fitted_joint(joint, fitted):
    """The robot joint carrying the fitted E-model joint ``fitted``.

    When the robot keeps a separate equivalent E-model joint (bearing in series with
    link bending), the fit belongs there; the physical joint takes the fitted gear
    torsion, which link bending does not change.
    """
    if joint.emodel is None:
        return replace(joint, model=fitted)
    return replace(joint, emodel=fitted, model=replace(joint.model, torsion=fitted.torsion))


def robot_with_effects(robot: Robot, arm: ArmModel, effects) -> tuple[Robot, list[Effect]]:
    """Robot with the linear effects built in, and the nonlinear effects (resolved)."""
    linear = [e for e in effects if e.kind not in _NONLINEAR]
    nonlinear = [resolve(e, arm) for e in effects if e.kind in _NONLINEAR]
    new, _ = apply_effects(arm, linear)
    joints = tuple(_fitted_joint(j, m) for j, m in zip(robot.joints, new.joints, strict=True))
    base = robot.base
    if new.foundation is not None:
        base = BaseSupport("spring", tuple(map(tuple, np.asarray(new.foundation).tolist())),
                           robot.base.damping_ratio)
    wrist = None if new.wrist_stiffness is None else tuple(
        map(tuple, np.asarray(new.wrist_stiffness).tolist()))
    links = robot.links
    c = sum(e.get("compliance") for e in effects if e.kind == "links")
    if c > 0:  # link flexibility: the flexible model with Young's modulus E / c
        links = tuple(replace(lk, material=replace(lk.material, E=lk.material.E / c))
                      for lk in robot.links)
    return replace(robot, joints=joints, base=base, wrist_stiffness=wrist,
                   links=links), nonlinear


def write_robot(path, robot: Robot, nonlinear=()) -> Path:
    """Write ``robot`` (TOML, atomic) with a ``[nonlinear]`` table for the joint laws."""
    import tomli_w

    from ..assembly.formats.toml import to_dict

    path = Path(path)
    data = to_dict(robot, path.resolve().parent)
    table: dict = {}
    for e in nonlinear:
        d = table.setdefault(robot.joint_names[e.joint], {})
        if e.kind == "backlash":
            d["backlash_rad"] = e.get("width")
        elif e.kind == "hardening":
            d["hardening_extra_rad_per_Nm"] = e.get("extra")
            d["hardening_threshold_Nm"] = e.get("threshold")
        else:
            d["hysteresis_lost_rad"] = e.get("lost")
            d["hysteresis_radius_Nm"] = e.get("radius")
    if table:
        data["nonlinear"] = table
    with atomic_path(path) as tmp:
        tmp.write_bytes(tomli_w.dumps(data).encode())
    return path


def read_robot_effects(path) -> tuple[Robot, list[Effect]]:
    """Read a robot TOML and its optional ``[nonlinear]`` table as effects."""
    from ..assembly.formats import read

    robot = read(path)
    with open(path, "rb") as fh:
        table = tomllib.load(fh).get("nonlinear", {})
    names = list(robot.joint_names)
    effects = []
    for jname, d in table.items():
        if jname not in names:
            raise ValueError(f"{path}: nonlinear.{jname}: no such joint (have {names})")
        j = names.index(jname)
        if "backlash_rad" in d:
            effects.append(Effect("backlash", j, (("width", float(d["backlash_rad"])),)))
        if "hardening_extra_rad_per_Nm" in d:
            effects.append(Effect("hardening", j, (
                ("extra", float(d["hardening_extra_rad_per_Nm"])),
                ("threshold", float(d["hardening_threshold_Nm"])))))
        if "hysteresis_lost_rad" in d:
            effects.append(Effect("hysteresis", j, (
                ("lost", float(d["hysteresis_lost_rad"])),
                ("radius", float(d["hysteresis_radius_Nm"])))))
    return robot, effects


def write_history(folder, diagnosis) -> list[Path]:
    """``history.csv``, ``history.json`` and ``history.png``: error of each model version."""
    plt = pyplot()

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    rows = [{"version": i, "model": s.label, "chi2_red": s.chi2_red, "band_lo": s.band[0],
             "band_hi": s.band[1], "rms_fit_um": s.rms_fit * 1e6,
             "rms_heldout_um": s.rms_heldout * 1e6} for i, s in enumerate(diagnosis.steps)]
    out = [folder / "history.csv", folder / "history.json", folder / "history.png"]
    with open(out[0], "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    out[1].write_text(json.dumps({"versions": rows, "accepted": [e.to_dict() for e in
                                                                 diagnosis.accepted]}, indent=2))
    fig, ax = plt.subplots(figsize=(6, 3.2))
    x = np.arange(len(rows))
    ax.bar(x - 0.2, [r["rms_fit_um"] for r in rows], 0.4, label="fitted series")
    ax.bar(x + 0.2, [r["rms_heldout_um"] for r in rows], 0.4, label="held-out series")
    ax.set_xticks(x, [f"v{r['version']}" for r in rows])
    ax.set_ylabel("RMS error [um]")
    ax.legend(fontsize=8)
    ax.set_title(" -> ".join(r["model"].split(" + ")[-1] for r in rows), fontsize=7)
    fig.tight_layout()
    fig.savefig(out[2], dpi=90)
    plt.close(fig)
    return out
