"""Session setup shared by the tests and the docstring examples (``--doctest-modules``)."""

from __future__ import annotations

import os

import pytest


@pytest.fixture(scope="session", autouse=True)
def _session_cache(tmp_path_factory):
    """One cache folder for the whole run: tet meshes, mass properties and superelements
    are computed once and shared by every test that asks for the same inputs.

    Never the user's cache.  ``FLEXARM_TEST_CACHE=DIR`` keeps it between runs (the demo
    arm's links take minutes to mesh cold); tests that need an empty cache set their own.
    """
    old = os.environ.get("FLEXARM_CACHE")
    keep = os.environ.get("FLEXARM_TEST_CACHE")
    if keep is None and os.environ.get("PYTEST_XDIST_WORKER"):
        # parallel workers share one folder (the cache is safe for concurrent writers), so
        # each robot is meshed once, not once per worker
        shared = tmp_path_factory.getbasetemp().parent / "flexarm_cache"
        shared.mkdir(exist_ok=True)
        keep = str(shared)
    os.environ["FLEXARM_CACHE"] = keep or str(tmp_path_factory.mktemp("flexarm_cache"))
    yield
    if old is None:
        os.environ.pop("FLEXARM_CACHE", None)
    else:
        os.environ["FLEXARM_CACHE"] = old
