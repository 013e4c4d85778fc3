import os
from importlib.resources import files

import pytest

from flexarm.assembly import emodel
from flexarm.assembly.formats.rapid import read_rapid
from flexarm.meshes.demo_arm import load_demo_robot


@pytest.fixture(scope="package", autouse=True)
def _session_cache(request, tmp_path_factory):
    """Overrides the assembly tests' per-session cache with one kept between runs
    (pytest's cache folder): the coarse flexible arm is meshed and reduced once (~3 min),
    then loads in a fraction of a second."""
    cache = getattr(request.config, "cache", None)
    path = cache.mkdir("flexarm_contact") if cache else tmp_path_factory.mktemp("flexarm_cache")
    old = os.environ.get("FLEXARM_CACHE")
    os.environ["FLEXARM_CACHE"] = str(path)
    yield
    if old is None:
        os.environ.pop("FLEXARM_CACHE", None)
    else:
        os.environ["FLEXARM_CACHE"] = old


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
