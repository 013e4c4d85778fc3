from importlib.resources import files

import pytest

from flexarm.assembly import emodel
from flexarm.assembly.formats.rapid import read_rapid
from flexarm.meshes.demo_arm import load_demo_robot


@pytest.fixture(scope="package")
def robot():
    return load_demo_robot()


@pytest.fixture(scope="package")
def arm(robot):
    return emodel(robot, method="surface")


@pytest.fixture(scope="package")
def module():
    return read_rapid(files("flexarm") / "data" / "rapid" / "ldbb_thesis.mod")


@pytest.fixture(scope="package")
def flex_arm(robot):
    """CB(10) flexible demo arm on a coarse 60 mm mesh (cached build)."""
    from flexarm.assembly.contact.circle_models import circle_arm

    return circle_arm(robot, "cb", mesh_size=0.06, n_modes=10)
