"""Link flexibility as a candidate effect: the E-model's rigid links -> the flexible model's.

The effect ``links`` has one amplitude, ``compliance`` ``c`` [-]: the links' compliance
as a multiple of the flexible model's (``c = 0`` is the E-model, ``c = 1`` the flexible
model built from the CAD with the nominal Young's modulus).  Every superelement
stiffness scales as ``K / c``; masses stay (a Craig-Bampton body's fixed-interface
modes do not change under a uniform scaling of ``K``, so this is the exact flexible
model with ``E / c``).  The joints, foundation and wrist of the model being diagnosed
are kept, so the effect changes only the links.  Its *signature* on a data set is the
flexible-model prediction minus the E-model prediction of the same data.
"""

from __future__ import annotations

from dataclasses import replace

from ..robot.effects import Effect
from .system import ArmModel

__all__ = ["links_arm", "split_links"]


def split_links(effects) -> tuple[float, list[Effect]]:
    """(link compliance factor ``c`` (0 if absent), the other effects)."""
    c, rest = 0.0, []
    for e in effects:
        if e.kind == "links":
            c += e.get("compliance")
        else:
            rest.append(e)
    return c, rest


def links_arm(arm: ArmModel, flexible: ArmModel | None, c: float) -> ArmModel:
    """``arm`` with the flexible model's links at compliance factor ``c`` [-].

    Parameters
    ----------
    arm : ArmModel
        The model being diagnosed (rigid links; its joints, foundation and wrist are kept).
    flexible : ArmModel or None
        The flexible model of the same robot (superelement bodies).
    c : float
        Link compliance factor; ``0`` returns ``arm`` itself.

    Examples
    --------
    >>> from flexarm.assembly.examples import two_link_arm
    >>> arm = two_link_arm()
    >>> links_arm(arm, None, 0.0) is arm
    True
    """
    if c == 0.0:
        return arm
    if flexible is None:
        raise ValueError("the link-flexibility effect needs the flexible model of the robot")
    if c < 0:
        raise ValueError(f"link compliance factor must be >= 0, got {c}")
    bodies = tuple(b if b.is_rigid else replace(b, K=b.K / c) for b in flexible.bodies)
    return replace(arm, bodies=bodies)
