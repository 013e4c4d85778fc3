"""apply_effects / resolve: a stiffness scale multiplies the torsion compliance, tilt and base
compliances add in series, hardening ratios become 1/(r k) - 1/k, wrist correlations become
couplings rho sqrt(c_i c_j); nonlinear laws come back per joint; the input arm is kept."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.assembly.analyses import tcp_compliance
from flexarm.assembly.effects import SignedLaw, apply_effects, resolve, wrist_compliance
from flexarm.assembly.examples import two_link_arm
from flexarm.assembly.nonlinear import Backlash, Hardening, Hysteresis
from flexarm.assembly.tolerances import tol
from flexarm.robot.effects import Effect, parse_effect

K1, K2 = 1e4, 2e4


@pytest.fixture(scope="module")
def demo_arm(demo_robot):
    from flexarm.assembly.emodel import emodel

    return emodel(demo_robot, method="surface")


def test_stiffness_scale_doubles_the_torsion_compliance():
    arm = two_link_arm(K1, K2)
    new, laws = apply_effects(arm, [parse_effect("stiffness:j1=0.5")])
    assert laws == {} and new.joints[0].torsion == K1 / 2 and new.joints[1] == arm.joints[1]
    C0, C = tcp_compliance(arm, [0.0, 0.0]), tcp_compliance(new, [0.0, 0.0])
    assert C[5, 5] == pytest.approx(2 / K1 + 1 / K2, rel=1e-13)
    assert C[1, 1] - C0[1, 1] == pytest.approx(4.0 / K1, rel=1e-12)  # (2L)^2 / k1 more
    assert arm.joints[0].torsion == K1  # the input arm is unchanged
    # a fit may probe a scale <= 0: it is floored, the stiffness stays finite and positive
    floored, _ = apply_effects(arm, [Effect("stiffness", 1, (("scale", -3.0),))])
    assert floored.joints[1].torsion == pytest.approx(K2 / tol.min_compliance_scale)


def test_tilt_adds_a_bearing_in_series():
    arm = two_link_arm(K1, K2)
    new, _ = apply_effects(arm, [parse_effect("tilt:j2=1e7")])
    assert new.joints[1].tilt == pytest.approx(1e7) and new.joints[1].tilt2 is None
    assert new.layout["n"] == 4 and arm.layout["n"] == 2  # the layout is rebuilt
    # tilt about the link axis x at joint 2 lifts the TCP (1 m out) by 1/k_tilt per N
    C = tcp_compliance(new, [0.0, 0.0])
    assert C[2, 2] == pytest.approx(1e-7, rel=1e-12)


def test_tilt_on_equivalent_joint_keeps_both_tilts(demo_arm):
    j2 = demo_arm.joints[1]
    new, _ = apply_effects(demo_arm, [Effect("tilt", 1, (("compliance", 2e-8),))])
    assert new.joints[1].tilt == pytest.approx(1 / (1 / j2.tilt + 2e-8), rel=1e-14)
    assert new.joints[1].tilt2 == pytest.approx(1 / (1 / j2.tilt_2 + 2e-8), rel=1e-14)
    rigid, _ = apply_effects(demo_arm, [Effect("tilt", 1, (("compliance", -1.0),))])
    assert rigid.joints[1].tilt == np.inf and rigid.joints[1].tilt2 == np.inf


def test_base_springs_in_series():
    arm = two_link_arm()
    one, _ = apply_effects(arm, [parse_effect("base:k=2e7")])
    r = tol.rigid_foundation
    np.testing.assert_allclose(one.foundation, np.diag([r, r, r, 2e7, 2e7, r]))
    two, _ = apply_effects(arm, [parse_effect("base:k=2e7"), parse_effect("base:k=3e7")])
    k = 1 / (1 / 2e7 + 1 / 3e7)
    np.testing.assert_allclose(np.diag(two.foundation), [r / 2] * 3 + [k, k, r / 2], rtol=1e-12)
    none, _ = apply_effects(arm, [Effect("base", None, (("compliance", -1e-8),))])
    assert none.foundation is None


def test_nonlinear_laws_per_joint():
    arm = two_link_arm(K1, K2)
    effects = [parse_effect("backlash:j2=0.1mrad"), parse_effect("hardening:j1=0.5,t=300Nm"),
               parse_effect("hysteresis:j2=0.05mrad,r=80Nm"),
               Effect("backlash", 0, (("width", -2e-4),)), parse_effect("links:c=2")]
    new, laws = apply_effects(arm, effects)
    assert new.joints == arm.joints  # the laws do not touch the linear springs
    assert laws[1] == [Backlash(1e-4), Hysteresis(5e-5, 80.0)]
    hard, signed = laws[0]
    # K1 / K2 = 0.5 below the threshold: extra compliance 1 / (0.5 k) - 1 / k
    assert hard == Hardening(300.0, pytest.approx(1 / K1))
    assert isinstance(signed, SignedLaw) and signed.amplitude == -2e-4
    np.testing.assert_allclose(signed.deflection([-5.0, 5.0]), [1e-4, -1e-4])


def test_resolve_converts_relative_forms():
    arm = two_link_arm(K1, K2)
    h = resolve(parse_effect("hardening:j2=0.25,t=100Nm"), arm)
    assert h.params == (("extra", pytest.approx(3 / K2)), ("threshold", 100.0))
    assert resolve(parse_effect("tilt:j1=4e6"), arm).params == (("compliance", 2.5e-7),)
    assert resolve(parse_effect("base:k=5e6"), arm).params == (("compliance", 2e-7),)
    si = Effect("hardening", 0, (("extra", 1e-6), ("threshold", 50.0)))
    assert resolve(si, arm) is si


def test_wrist_correlations_become_couplings(demo_arm):
    k = np.array([j.torsion for j in demo_arm.joints[3:]])
    c = 1 / k
    np.testing.assert_allclose(wrist_compliance(demo_arm), np.diag(c), rtol=1e-15)
    new, _ = apply_effects(demo_arm, [parse_effect("wrist:c45=0.5,c56=-0.3")])
    expected = np.diag(c)
    expected[0, 1] = expected[1, 0] = 0.5 * np.sqrt(c[0] * c[1])
    expected[1, 2] = expected[2, 1] = -0.3 * np.sqrt(c[1] * c[2])
    atol = 1e-12 * c.max()
    np.testing.assert_allclose(np.linalg.inv(new.wrist_stiffness), expected, rtol=1e-12,
                               atol=atol)
    np.testing.assert_allclose(wrist_compliance(new), expected, rtol=1e-12, atol=atol)
    # a torsion scale on a wrist joint after the coupling scales its row and column
    both, _ = apply_effects(demo_arm, [parse_effect("wrist:c45=0.5,c56=-0.3"),
                                       parse_effect("stiffness:j5=0.25")])
    S = np.diag([1.0, 2.0, 1.0])  # sqrt(scale 4) on joint 5
    np.testing.assert_allclose(wrist_compliance(both), S @ expected @ S, rtol=1e-12,
                               atol=4 * atol)
    assert apply_effects(demo_arm, [])[0].wrist_stiffness is None


def test_wrist_correlation_does_not_depend_on_the_order_of_effects(demo_arm):
    wrist, scale = parse_effect("wrist:c45=0.5"), parse_effect("stiffness:j5=0.25")
    for effects in ([wrist, scale], [scale, wrist]):
        C = wrist_compliance(apply_effects(demo_arm, effects)[0])
        assert C[0, 1] / np.sqrt(C[0, 0] * C[1, 1]) == pytest.approx(0.5, rel=1e-12)
