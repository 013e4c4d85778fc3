"""Placeholder stiffness scaled to three published robots (E-model only, no seats):
each robot's first E-model frequency at its mid-workspace pose lies in the band the
size rule promises for it, and the import says where its mass comes from."""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest

from flexarm.assembly.analyses import natural_frequencies
from flexarm.assembly.emodel import emodel
from flexarm.robot.placeholder_stiffness import mid_workspace_pose
from flexarm.studies.import_urdf import import_urdf

SHARED = Path(__file__).resolve().parents[3] / "shared/data"
#: robot: (URDF, datasheet mass [kg], datasheet reach [m])
ROBOTS = {
    "irb4600": (SHARED / "irb4600/urdf/irb4600_60_205.urdf", 425.0, 2.05),
    "m20ia": (SHARED / "robots/fanuc_m20ia/urdf/m20ia.urdf", 250.0, 1.811),
    "ur10": (SHARED / "robots/ur10/urdf/ur10.urdf", 28.9, 1.3),
}


@pytest.fixture(scope="module", params=sorted(ROBOTS))
def imported(request, tmp_path_factory):
    urdf, mass, _ = ROBOTS[request.param]
    if not urdf.is_file():
        pytest.skip(f"no published description at {urdf}")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the UR10's open forearm: not this test's subject
        imp = import_urdf(urdf, mass_kg=mass, regions=False,
                          derived_dir=tmp_path_factory.mktemp(request.param))
    return request.param, imp


def test_first_emodel_mode_in_the_promised_band(imported):
    name, imp = imported
    robot = imp.robot
    q = mid_workspace_pose(robot.chain, robot.lower, robot.upper)
    f1 = natural_frequencies(emodel(robot), q)[0]
    lo, hi = imp.stiffness.band_hz
    assert lo < f1 < hi, (name, f1, (lo, hi))
    # the wrist centre is where the datasheets measure reach (the UR10's 1.3 m is to
    # the flange, 0.1 m beyond)
    tol = 0.1 if name == "ur10" else 0.01
    assert imp.stiffness.size.reach == pytest.approx(ROBOTS[name][2], abs=tol)


def test_placeholders_stay_marked_and_scaled(imported):
    name, imp = imported
    models = [j.model for j in imp.robot.joints]
    assert all(m.is_placeholder for m in models)
    assert [m.torsion for m in models] == pytest.approx(list(imp.stiffness.torsion))
    k2 = {"irb4600": 4.27e6, "m20ia": 2.22e6, "ur10": 1.7e5}[name]
    assert models[1].torsion == pytest.approx(k2, rel=0.03)
    lines = imp.report()
    assert any(line.startswith("placeholder size rule: ") for line in lines)


def test_mass_line_compares_inertials_with_the_datasheet(imported):
    name, imp = imported
    note = imp.mass_note
    assert note.count("\n") == 0 and note in imp.report()
    if name == "ur10":  # the inertials sum to 32.7 kg against 28.9 kg
        assert "URDF <inertial> 32.7 kg, +13.1 % vs the datasheet 28.9 kg" in note
        assert imp.stiffness.size.effort == (330.0, 330.0, 150.0, 56.0, 56.0, 56.0)
    else:
        assert "no URDF <inertial>" in note and imp.stiffness.size.effort is None
