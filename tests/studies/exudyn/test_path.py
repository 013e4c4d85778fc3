"""The loaded circle in time on the Exudyn model: joints driven through their gear
springs along the thesis's RAPID circle, gravity on, the bar force ramped in; slowly
driven, the deviation caused by the bar force is the quasi-static circle's within 2 %
of its amplitude; fast, it departs from it."""

import numpy as np
import pytest

from flexarm.assembly.arm import ArmSpec, build_arm

pytest.importorskip("exudyn", reason="Exudyn (pip install flexarm[mbs]) runs the "
                                     "flexible-multibody model")

from flexarm.studies.exudyn.path import exudyn_circle  # noqa: E402 - after the skip


@pytest.fixture(scope="module")
def emodel(demo_robot):
    return build_arm(demo_robot)


def test_slow_circle_is_quasi_static(emodel, tmp_path):
    res = exudyn_circle(emodel, proc="Path_30", force=200.0, speed=0.1)
    assert res.t[-1] == pytest.approx(2 * np.pi * 0.155 / 0.1, rel=0.02)  # one turn
    assert res.error < 0.02  # acceptance (at v10; here ten times faster)
    assert 3e-4 < np.abs(res.bar).max() < 1e-3  # hundreds of µm at 200 N
    assert [p.name for p in res.write(tmp_path)] == ["path_Path_30.png"]


def test_fast_path_departs_from_quasi_static(emodel):
    res = exudyn_circle(emodel, proc="Path_20", force=200.0)  # v1000 as programmed
    assert res.speed == 1.0 and res.t[-1] < 1.0
    assert 0.05 < res.error < 0.5  # dynamics: the deviation oscillates about the static one


@pytest.mark.slow
@pytest.mark.parametrize("spec", [ArmSpec("emodel"), ArmSpec("cb", mesh_size=0.06,
                                                              n_modes=10)],
                         ids=["emodel", "cb"])
def test_programmed_v10_circle(demo_robot, spec):
    res = exudyn_circle(build_arm(demo_robot, spec), proc="Path_30", force=200.0)
    assert res.speed == pytest.approx(0.01)
    assert res.error < 0.02  # acceptance: within 2 % of the amplitude
