"""Fixtures for the assembly tests: the demo arm (the cache folder is tests/conftest.py's)."""

from __future__ import annotations

import pytest


@pytest.fixture(scope="session")
def demo_robot():
    from flexarm.meshes.demo_arm import load_demo_robot

    return load_demo_robot()


@pytest.fixture(scope="session")
def demo_emodel(demo_robot):
    """E-model of the demo arm with mass properties of its tetrahedral meshes."""
    from flexarm.assembly.emodel import emodel

    return emodel(demo_robot, method="tets")


def pytest_collection_modifyitems(config, items):
    """Skip ``slow`` tests of this folder unless selected with ``-m slow``."""
    if "slow" in (config.getoption("-m") or ""):
        return
    skip = pytest.mark.skip(reason="slow: run with -m slow")
    for item in items:
        if "slow" in item.keywords and "tests/assembly" in str(item.fspath).replace("\\", "/"):
            item.add_marker(skip)


@pytest.fixture(scope="session")
def box_robot(tmp_path_factory):
    """The three-link box arm of ``box_arm.py`` (STL + TOML in a temporary folder)."""
    from .box_arm import box_arm_robot

    return box_arm_robot(tmp_path_factory.mktemp("box_arm"))
