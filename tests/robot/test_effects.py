"""Named effects: every command-line form of parse_effect with its SI parameters (units mrad,
urad, deg, kNm), defaults, the exact error messages, and the Effect record (label, get,
with_params, dict round trip)."""

from __future__ import annotations

import math
import re

import pytest

from flexarm.robot.effects import KINDS, NONLINEAR, Effect, parse_effect


def exact(message: str) -> str:
    return "^" + re.escape(message) + "$"


@pytest.mark.parametrize("spec, kind, joint, params", [
    ("backlash:j2=0.1mrad", "backlash", 1, {"width": 1e-4}),
    ("Backlash: J6 = 2urad", "backlash", 5, {"width": 2e-6}),
    ("backlash:j1=0.01deg", "backlash", 0, {"width": math.radians(0.01)}),
    ("hardening:j1=0.5,t=400Nm", "hardening", 0, {"ratio": 0.5, "threshold": 400.0}),
    ("hardening:j3=0.8", "hardening", 2, {"ratio": 0.8, "threshold": 400.0}),
    ("hardening:j3=0.8,t=1.5kNm", "hardening", 2, {"ratio": 0.8, "threshold": 1500.0}),
    ("hysteresis:j2=0.1mrad,r=250Nm", "hysteresis", 1, {"lost": 1e-4, "radius": 250.0}),
    ("hysteresis:j2=0.1mrad", "hysteresis", 1, {"lost": 1e-4, "radius": 300.0}),
    ("tilt:j2=1e7", "tilt", 1, {"stiffness": 1e7}),
    ("tilt:j2=2e7Nm/rad", "tilt", 1, {"stiffness": 2e7}),
    ("base:k=3e7", "base", None, {"stiffness": 3e7}),
    ("base:", None, None, None),
    ("wrist:c45=0.5,c56=-0.3", "wrist", None, {"rho45": 0.5, "rho56": -0.3}),
    ("stiffness:j3=1.25", "stiffness", 2, {"scale": 0.8}),
    ("links:c=0.5", "links", None, {"compliance": 0.5}),
])
def test_forms(spec, kind, joint, params):
    if kind is None:  # "KIND:" alone has no KEY=VALUE
        with pytest.raises(ValueError, match=exact(f"effect '{spec}': '' is not KEY=VALUE")):
            parse_effect(spec)
        return
    e = parse_effect(spec)
    assert (e.kind, e.joint) == (kind, joint)
    assert [k for k, _ in e.params] == list(params)
    for k, v in params.items():
        assert e.get(k) == pytest.approx(v, rel=1e-14)


def test_defaults_of_base_and_links():
    assert parse_effect("base:x=1").get("stiffness") == 2e7
    assert parse_effect("links:x=1").get("compliance") == 1.0
    assert parse_effect("wrist:x=1").params == ()


@pytest.mark.parametrize("spec, message", [
    ("backlash", "effect 'backlash': expected KIND:KEY=VALUE[,KEY=VALUE]"),
    ("backlash:j2", "effect 'backlash:j2': 'j2' is not KEY=VALUE"),
    ("backlash:j7=1mrad", "effect 'backlash:j7=1mrad': joint 7 outside 1..6"),
    ("backlash:j0=1mrad", "effect 'backlash:j0=1mrad': joint 0 outside 1..6"),
    ("tilt:k=1e7", "effect 'tilt:k=1e7': name the joint, e.g. tilt:j2=..."),
    ("stiffness:c=2", "effect 'stiffness:c=2': name the joint, e.g. stiffness:j2=..."),
    ("backlash:j2=1parsec", "effect 'backlash:j2=1parsec': backlash width 1parsec: unknown "
                            "angle unit 'parsec' (accepted: deg, rad, mrad, urad)"),
    ("wobble:j2=1", "effect 'wobble:j2=1': unknown kind 'wobble' (known: "
                    + ", ".join(KINDS) + ")"),
])
def test_errors(spec, message):
    with pytest.raises(ValueError, match=exact(message)):
        parse_effect(spec)


def test_joint_range_follows_n_joints():
    assert parse_effect("backlash:j7=1mrad", n_joints=7).joint == 6
    with pytest.raises(ValueError, match="joint 4 outside 1..3"):
        parse_effect("backlash:j4=1mrad", n_joints=3)


def test_effect_record():
    e = Effect("hysteresis", 2, (("lost", 1e-4), ("radius", 300.0)))
    assert e.label == "joint 3 hysteresis" and Effect("base").label == "base"
    assert e.get("radius") == 300.0 and e.get("missing", 7.0) == 7.0
    with pytest.raises(KeyError, match="effect hysteresis has no parameter 'missing'"):
        e.get("missing")
    f = e.with_params(radius=200, extra=1)
    assert f.params == (("lost", 1e-4), ("radius", 200.0), ("extra", 1.0))
    assert e.get("radius") == 300.0  # frozen: a new record
    assert Effect.from_dict(e.to_dict()) == e
    assert e.to_dict() == {"kind": "hysteresis", "joint_number": 3,
                           "params": {"lost": 1e-4, "radius": 300.0}}
    # files written before joints were numbered from 1 still read
    assert Effect.from_dict({"kind": "hysteresis", "joint": 2,
                             "params": {"lost": 1e-4, "radius": 300.0}}) == e
    assert Effect.from_dict(Effect("frame", None).to_dict()).joint is None
    with pytest.raises(ValueError, match="unknown effect kind 'creep'"):
        Effect("creep", 0)


def test_nonlinear_kinds():
    assert NONLINEAR == ("backlash", "hardening", "hysteresis")
    assert set(NONLINEAR) < set(KINDS)
