"""Model versions: the updated robot description, the error history and its plot.

:func:`robot_with_effects` builds the accepted effects into a new
:class:`~flexarm.robot.description.Robot`: linear effects as its joint, foundation and
wrist springs (link flexibility ``c`` as the links' Young's modulus ``E / c``, used by the
flexible model), nonlinear joint laws as its ``effects`` (the robot file's
``[nonlinear]`` table).  Write it with :func:`flexarm.robot.formats.write`.
"""

from __future__ import annotations

import csv
import json
from dataclasses import replace
from pathlib import Path

import numpy as np

from ...assembly.effects import apply_effects, body_centre_of_mass, resolve
from ...assembly.system import ArmModel
from ...fe.files import writes_folder
from ...robot.description import BaseSupport, LumpedMass, Robot
from ...robot.effects import NONLINEAR, STORED
from ..static.plots import plot_history

__all__ = ["robot_with_effects", "write_history"]


#: Effects whose fit identifies a joint's torsion (what an import leaves as a placeholder).
_JOINT_FITS = ("stiffness",)


def _fitted_joint(joint, fitted, identified: bool = False):
    """The robot joint carrying the fitted E-model joint ``fitted``.

    When the robot keeps a separate equivalent E-model joint (bearing in series with
    link bending), the fit belongs there; the physical joint takes the fitted gear
    torsion, which link bending does not change.  An ``identified`` joint (a fit wrote
    its springs) is no longer a placeholder.
    """
    model = fitted if joint.emodel is None else replace(joint.model, torsion=fitted.torsion)
    if identified:
        fitted, model = replace(fitted, source="given"), replace(model, source="given")
    if joint.emodel is None:
        return replace(joint, model=model)
    return replace(joint, emodel=fitted, model=model)


def robot_with_effects(robot: Robot, arm: ArmModel, effects) -> Robot:
    """``robot`` with the linear ``effects`` built into its springs, and the nonlinear
    ones (resolved to their SI model form against ``arm``) and those of kind
    :data:`~flexarm.robot.effects.STORED` (tool, balancer, frame, load cell, reflector)
    as its ``effects``; an added mass becomes a lumped mass of its link.

    A joint whose torsion a ``stiffness`` effect fitted loses its placeholder
    mark (:attr:`~flexarm.robot.joints.JointModel.source` becomes ``"given"``).
    """
    linear = [e for e in effects if e.kind not in NONLINEAR + STORED + ("mass",)]
    kept = tuple(resolve(e, arm) for e in effects if e.kind in NONLINEAR + STORED)
    new, _ = apply_effects(arm, linear)
    identified = {e.joint for e in linear if e.kind in _JOINT_FITS and e.joint is not None}
    joints = tuple(_fitted_joint(j, m, i in identified)
                   for i, (j, m) in enumerate(zip(robot.joints, new.joints, strict=True)))
    base = robot.base
    if new.foundation is not None:
        base = BaseSupport("spring", tuple(map(tuple, np.asarray(new.foundation).tolist())),
                           robot.base.damping_ratio)
    wrist = None if new.wrist_stiffness is None else tuple(
        map(tuple, np.asarray(new.wrist_stiffness).tolist()))
    links = list(robot.links)
    for e in effects:  # an added mass at its link's centre of mass, as the fit put it
        if e.kind == "mass" and e.get("mass") > 0:
            link = links[e.joint + 1]
            com = body_centre_of_mass(arm.bodies[e.joint + 1])
            extra = LumpedMass("added mass (diagnose)", float(e.get("mass")),
                               tuple(float(v) for v in com))
            links[e.joint + 1] = replace(link, lumped=tuple(link.lumped) + (extra,))
    links = tuple(links)
    c = sum(e.get("compliance") for e in effects if e.kind == "links")
    if c > 0:  # link flexibility: the flexible model with Young's modulus E / c
        links = tuple(replace(lk, material=replace(lk.material, E=lk.material.E / c))
                      for lk in robot.links)
    return replace(robot, joints=joints, base=base, wrist_stiffness=wrist, links=links,
                   effects=kept)


@writes_folder()
def write_history(folder, diagnosis, nominal_rms: float | None = None,
                  sigma: float | None = None, what: str = "") -> list[Path]:
    """``history.csv``, ``history.json`` and ``history.png``: error of each model version
    (the plot from the ``nominal_rms`` [m] model down, with the noise floor of ``sigma``
    [m] and the model and poses ``what`` in the title:
    :func:`~flexarm.validation.static.plots.plot_history`)."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    rows = [{"version": i, "model": s.label, "chi2_red": s.chi2_red, "band_lo": s.band[0],
             "band_hi": s.band[1], "rms_fit_um": s.rms_fit * 1e6,
             "rms_heldout_um": s.rms_heldout * 1e6, "freq_rms_pct": 100 * s.freq_rms,
             "unpaired_modes": s.n_unpaired} for i, s in enumerate(diagnosis.steps)]
    out = [folder / "history.csv", folder / "history.json", folder / "history.png"]
    # the nominal model's row first: the plot starts from it (fitted on every series,
    # so it has no held-out error)
    nominal = ([{"version": "nominal", "model": "nominal (as built)", "chi2_red": "",
                 "band_lo": "", "band_hi": "", "rms_fit_um": nominal_rms * 1e6,
                 "rms_heldout_um": "", "freq_rms_pct": "", "unpaired_modes": ""}]
               if nominal_rms is not None else [])
    with open(out[0], "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(nominal + rows)
    out[1].write_text(json.dumps({
        "nominal_rms_um": None if nominal_rms is None else nominal_rms * 1e6,
        "versions": rows, "accepted": [e.to_dict() for e in diagnosis.accepted]}, indent=2))
    plot_history(out[2], rows, nominal_rms, sigma, what)
    return out
