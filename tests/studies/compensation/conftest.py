"""Fixtures of the compensation tests: the demo arm, its E-model and the shipped programs."""

from importlib.resources import files

import pytest

from flexarm.assembly import emodel

#: The thesis's appendix-B module and the milling example (``flexarm/data/rapid``).
THESIS = files("flexarm") / "data" / "rapid" / "ldbb_thesis.mod"
MILLING = files("flexarm") / "data" / "rapid" / "milling_demo.mod"


@pytest.fixture(scope="package")
def robot(demo_robot):
    """The demo arm (the session's)."""
    return demo_robot


@pytest.fixture(scope="package")
def arm(demo_robot):
    """Its E-model with the CAD surfaces' mass properties (no meshing)."""
    return emodel(demo_robot, method="surface")
