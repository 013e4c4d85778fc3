"""The ``[nonlinear]`` table of a robot TOML: nonlinear joint laws, one sub-table per
joint::

    [nonlinear.joint_2]
    backlash_rad = 1e-4                      # play [rad]
    hardening_extra_rad_per_Nm = 2e-8        # extra compliance below the threshold [rad/Nm]
    hardening_threshold_Nm = 3000.0          # torque where the joint stiffens [Nm]
    hysteresis_lost_rad = 5e-5               # lost motion [rad]
    hysteresis_radius_Nm = 800.0             # torque radius of the hysteresis [Nm]

read into ``Robot.effects`` (:class:`~flexarm.robot.effects.Effect`) and written back.
"""

from __future__ import annotations

from ..effects import Effect
from . import toml_keys as tk

__all__ = ["NONLINEAR_KEYS", "nonlinear_effects", "nonlinear_table"]

#: [nonlinear.<joint>] keys per effect kind: (file key, effect parameter)
NONLINEAR_KEYS = {
    "backlash": (("backlash_rad", "width"),),
    "hardening": (("hardening_extra_rad_per_Nm", "extra"), ("hardening_threshold_Nm", "threshold")),
    "hysteresis": (("hysteresis_lost_rad", "lost"), ("hysteresis_radius_Nm", "radius")),
}


def nonlinear_effects(table: dict, joint_names: list[str]) -> tuple[Effect, ...]:
    """Effects of the ``[nonlinear]`` table, joint by joint in file order."""
    allowed = {key for keys in NONLINEAR_KEYS.values() for key, _ in keys}
    effects = []
    for jname, d in table.items():
        where = f"nonlinear.{jname}"
        if jname not in joint_names:
            raise ValueError(f"{where}: no such joint (have {joint_names})")
        if not isinstance(d, dict):
            raise ValueError(f"{where} must be a table, got {d!r}")
        tk.check_keys(d, allowed, where)
        for kind, keys in NONLINEAR_KEYS.items():
            if keys[0][0] not in d:
                continue
            missing = [key for key, _ in keys if key not in d]
            if missing:
                raise ValueError(f"{where}.{missing[0]} is required with {keys[0][0]}")
            effects.append(Effect(kind, joint_names.index(jname),
                                  tuple((name, float(d[key])) for key, name in keys)))
    return tuple(effects)


def nonlinear_table(robot) -> dict:
    """The ``[nonlinear]`` table of ``robot.effects`` (empty when there are none)."""
    table: dict = {}
    for e in robot.effects:
        if e.kind not in NONLINEAR_KEYS:
            continue
        d = table.setdefault(robot.joint_names[e.joint], {})
        d.update({key: e.get(name) for key, name in NONLINEAR_KEYS[e.kind]})
    return table
