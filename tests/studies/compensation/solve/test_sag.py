import numpy as np
import pytest

from flexarm.assembly.analyses import gravity_sag as assembled_sag
from flexarm.assembly.effects import apply_effects
from flexarm.robot.effects import parse_effect
from flexarm.studies.compensation.solve.sag import gravity_sag


def _poses(robot, n=40, seed=0):
    rng = np.random.default_rng(seed)
    return robot.pose("P1") + rng.uniform(-0.5, 0.5, (n, 6))


@pytest.mark.parametrize("effects", [(), ("base:k=2e7", "tilt:j2=1e7", "wrist:c45=0.5")])
def test_equals_the_assembled_sag_on_the_emodel(robot, arm, effects):
    model, _ = apply_effects(arm, [parse_effect(e) for e in effects])
    q = _poses(robot)
    ref = assembled_sag(model, q)
    assert np.abs(gravity_sag(model, q) - ref).max() < 1e-12 * np.abs(ref).max()


def test_equals_the_assembled_sag_on_flexible_links(robot, flex_arm):
    q = _poses(robot, 12, seed=1)
    ref = assembled_sag(flex_arm, q)
    assert np.abs(gravity_sag(flex_arm, q) - ref).max() < 1e-12 * np.abs(ref).max()


def test_one_horizontal_link_sags_by_its_weight_over_the_spring():
    """A 10 kg rod of 1 m on a joint about y (k = 1e4 N m/rad): it turns by m g L / (2 k)
    and its tip drops by m g L^2 / (2 k)."""
    from flexarm.assembly.bodies import rigid_body
    from flexarm.assembly.system import ArmModel
    from flexarm.fe.mass_properties import MassProperties
    from flexarm.robot.joints import JointModel
    from flexarm.robot.kinematics import Chain

    m, L, k, g = 10.0, 1.0, 1e4, 9.80665
    tool = np.eye(4)
    tool[0, 3] = L
    chain = Chain(origins=[[0, 0, 0]], axes=[[0, 1, 0]], parents=[0], tool=tool)
    rod = MassProperties(m, np.array([L / 2, 0, 0]), np.diag([0, 1, 1]) * m * L**2 / 12)
    bodies = (rigid_body("base", MassProperties(1.0, np.zeros(3), np.eye(3)), [0, 0, 0],
                         {"joint_1": [0, 0, 0]}),
              rigid_body("rod", rod, [0, 0, 0], {"tcp": [L, 0, 0]}))
    arm = ArmModel(chain, bodies, (JointModel(torsion=k),), ("joint_1",), "tcp")
    s = gravity_sag(arm, np.zeros((1, 1)))[0]
    assert np.allclose(s, [0, 0, -m * g * L**2 / (2 * k), 0, m * g * L / (2 * k), 0],
                       rtol=1e-12, atol=1e-18)
