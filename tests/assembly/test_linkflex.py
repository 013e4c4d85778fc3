"""Link flexibility as an effect: the E-model's rigid links -> the flexible model's."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.assembly.examples import two_link_arm
from flexarm.assembly.linkflex import links_arm, split_links
from flexarm.robot.effects import parse_effect


@pytest.fixture(scope="module")
def flex(demo_robot):
    """(E-model, flexible model) of the demo arm on a coarse mesh, same tets for masses."""
    from flexarm.assembly.build import BuildOptions
    from flexarm.assembly.emodel import emodel
    from flexarm.assembly.flexible import flexible_arm

    return (emodel(demo_robot, method="tets", mesh_size=0.06),
            flexible_arm(demo_robot, BuildOptions(mesh_size=0.06, n_modes=4)))


def test_links_arm_limits(flex):
    """c -> 0 is the E-model; c = 1 is the flexible model (softer, lower frequencies)."""
    from flexarm.assembly.analyses import natural_frequencies, tcp_compliance

    ea, fa = flex
    q = np.zeros(6) + [0, -0.5, 0.8, 0, 0.6, 0]
    C0 = tcp_compliance(ea, q)[:3, :3]
    C_small = tcp_compliance(links_arm(ea, fa, 1e-6), q)[:3, :3]
    C1 = tcp_compliance(links_arm(ea, fa, 1.0), q)[:3, :3]
    assert np.allclose(C_small, C0, rtol=1e-4, atol=1e-12)
    assert np.all(np.diag(C1) > np.diag(C0))
    f0 = natural_frequencies(ea, q)[:4]
    f1 = natural_frequencies(links_arm(ea, fa, 1.0), q)[:4]
    assert np.all(f1 < f0)


def test_split_links_sums_factors_and_keeps_the_rest():
    effects = [parse_effect("links:c=0.5"), parse_effect("backlash:j2=0.1mrad"),
               parse_effect("links:c=0.25")]
    c, rest = split_links(effects)
    assert c == 0.75 and [e.kind for e in rest] == ["backlash"]


def test_links_arm_needs_the_flexible_model_and_a_positive_factor():
    arm = two_link_arm()
    with pytest.raises(ValueError, match="needs the flexible model"):
        links_arm(arm, None, 1.0)
    with pytest.raises(ValueError, match=">= 0"):
        links_arm(arm, arm, -1.0)
