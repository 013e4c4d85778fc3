import pytest

from flexarm.assembly import emodel
from flexarm.robot.demo_arm import load_demo_robot


@pytest.fixture(scope="package")
def robot():
    return load_demo_robot()


@pytest.fixture(scope="package")
def arm(robot):
    return emodel(robot, method="surface")
