"""The ``[[effects]]`` array of a robot TOML: fitted effects that are not springs of the
arm, one table each, SI values with the unit in the key::

    [[effects]]                  # a gravity balancer in parallel with joint 2's gear
    kind = "balancer"
    joint = "joint_2"
    kc_Nm_per_rad = 3.0e5        # stiffness kc cos q2 + ks sin q2 [N m/rad]
    ks_Nm_per_rad = 1.0e5

    [[effects]]                  # tool/adapter compliance in the tool frame
    kind = "tool"
    cxx_m_per_N = 1.0e-7         # ... cyy, czz, cxy, cxz, cyz

    [[effects]]                  # the tracker's frame, off by a small rotation and scale
    kind = "frame"
    rx_rad = 0.0                 # ... ry_rad, rz_rad
    scale = 0.002

    [[effects]]                  # the load cell reads 3 % high
    kind = "loadcell"
    scale = 0.03

    [[effects]]                  # the reflector sits off the TCP (tool frame)
    kind = "reflector"
    ox_m = 0.03                  # ... oy_m, oz_m

``diagnose --apply`` writes them; every prediction of the robot (``compare``, a second
``diagnose``) adds them to the arm's compliance, so the written file gives the
diagnosis's final model.  Joint laws keep their ``[nonlinear]`` table
(:mod:`~.toml_nonlinear`).
"""

from __future__ import annotations

import math

from ..effects import STORED, TOOL_PARAMS, Effect

__all__ = ["EFFECT_KEYS", "effects_from_tables", "effects_tables"]

#: Per kind, each parameter's file key (the unit in the suffix).
EFFECT_KEYS = {
    "tool": {p: f"{p}_m_per_N" for p in TOOL_PARAMS},
    "balancer": {"kc": "kc_Nm_per_rad", "ks": "ks_Nm_per_rad"},
    "frame": {"rx": "rx_rad", "ry": "ry_rad", "rz": "rz_rad", "scale": "scale"},
    "loadcell": {"scale": "scale"},
    "reflector": {"ox": "ox_m", "oy": "oy_m", "oz": "oz_m"},
}
assert set(EFFECT_KEYS) == set(STORED)
#: The kinds whose table names a joint.
_JOINTED = ("balancer",)


def effects_from_tables(tables: list[dict], joint_names: list[str]) -> tuple[Effect, ...]:
    """Effects of the ``[[effects]]`` array (every key checked, values finite).

    Examples
    --------
    >>> effects_from_tables([{"kind": "balancer", "joint": "j2", "kc_Nm_per_rad": 3e5}],
    ...                     ["j1", "j2"])
    (Effect(kind='balancer', joint=1, params=(('kc', 300000.0), ('ks', 0.0))),)
    """
    out = []
    for i, d in enumerate(tables):
        where = f"effects[{i}]"
        kind = d.get("kind")
        if kind not in EFFECT_KEYS:
            raise ValueError(f"{where}.kind must be one of {list(STORED)}, got {kind!r}")
        keys = EFFECT_KEYS[kind]
        allowed = {"kind", *keys.values()} | ({"joint"} if kind in _JOINTED else set())
        extra = sorted(set(d) - allowed)
        if extra:
            raise ValueError(f"{where}: unknown key '{extra[0]}' for kind '{kind}' "
                             f"(allowed: {sorted(allowed)})")
        joint = None
        if kind in _JOINTED:
            if d.get("joint") not in joint_names:
                raise ValueError(f"{where}.joint must name a joint ({joint_names}), got "
                                 f"{d.get('joint')!r}")
            joint = joint_names.index(d["joint"])
        params = []
        for name, key in keys.items():
            value = d.get(key, 0.0)
            if isinstance(value, bool) or not isinstance(value, int | float) \
                    or not math.isfinite(value):
                raise ValueError(f"{where}.{key} must be a finite number, got {value!r}")
            params.append((name, float(value)))
        out.append(Effect(kind, joint, tuple(params)))
    return tuple(out)


def effects_tables(effects, joint_names) -> list[dict]:
    """The ``[[effects]]`` array of the stored kinds among ``effects``."""
    out = []
    for e in effects:
        if e.kind not in EFFECT_KEYS:
            continue
        d: dict = {"kind": e.kind}
        if e.kind in _JOINTED:
            d["joint"] = joint_names[e.joint]
        d.update({key: e.get(name, 0.0) for name, key in EFFECT_KEYS[e.kind].items()})
        out.append(d)
    return out
