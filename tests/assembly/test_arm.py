"""build_arm / ArmSpec: the default spec is the E-model with CAD-surface masses (same TCP
compliance, frequencies and bodies as emodel), labels and build options, unknown models refused."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.assembly.analyses import natural_frequencies, tcp_compliance
from flexarm.assembly.arm import MASS_METHODS, MODELS, Arm, ArmSpec, build_arm
from flexarm.assembly.build import BuildOptions
from flexarm.assembly.emodel import emodel


def test_default_is_the_surface_emodel(demo_robot):
    arm = build_arm(demo_robot)
    assert isinstance(arm, Arm) and arm.robot is demo_robot and arm.builds is None
    assert arm.spec == ArmSpec() and arm.spec.label == "E-model"
    ref = emodel(demo_robot, method="surface")
    Q = np.stack([demo_robot.pose(p) for p in ("P1", "P2", "P3")])
    np.testing.assert_array_equal(tcp_compliance(arm.model, Q), tcp_compliance(ref, Q))
    np.testing.assert_array_equal(natural_frequencies(arm.model, Q), natural_frequencies(ref, Q))
    for a, b in zip(arm.model.bodies, ref.bodies, strict=True):
        np.testing.assert_array_equal(a.M, b.M)
    assert arm.model.joints == ref.joints and arm.model.joint_names == demo_robot.joint_names


def test_surface_mass_ignores_the_mesh_size(demo_robot):
    a = build_arm(demo_robot, ArmSpec(mesh_size=0.2)).model
    b = build_arm(demo_robot).model
    q = demo_robot.pose("P1")
    np.testing.assert_array_equal(tcp_compliance(a, q), tcp_compliance(b, q))


def test_labels_and_build_options():
    assert MODELS == ("emodel", "guyan", "cb", "full") and MASS_METHODS == ("surface", "tets")
    assert [ArmSpec(m).label for m in MODELS] == ["E-model", "Guyan", "CB", "Full FE"]
    assert ArmSpec("full", mesh_size=0.05).build_options() == BuildOptions("guyan", 0, "rbe2",
                                                                          0.05)
    spec = ArmSpec("guyan", n_modes=4, coupling="rbe3", mesh_size=0.05)
    assert spec.build_options() == BuildOptions("guyan", 4, "rbe3", 0.05)


@pytest.mark.parametrize("kwargs, message", [
    ({"model": "fe"}, "model must be one of emodel, guyan, cb, full, got 'fe'"),
    ({"mass": "volume"}, "mass must be one of surface, tets, got 'volume'"),
])
def test_unknown_model_or_mass_is_refused(kwargs, message):
    with pytest.raises(ValueError, match="^" + message + "$"):
        ArmSpec(**kwargs)
