"""Floating-frame body data of the links: six point masses carry a lumped mass's inertia
exactly; the points, mass matrix and mode basis of every link reassemble the link body's
mass matrix (lumped masses included) and keep its stiffness."""

import numpy as np
import pytest

from flexarm.assembly.arm import ArmSpec, build_arm
from flexarm.fe.mass_properties import MassProperties
from flexarm.studies.exudyn.bodies import body_mass_matrix, point_masses
from flexarm.studies.exudyn.model import ffrf_links


def _inertia(m, r):
    """Inertia [kg m^2] of point masses ``m`` at ``r`` (about the origin)."""
    return np.einsum("k,kij->ij", m, np.einsum("ki,ki->k", r, r)[:, None, None] * np.eye(3)
                     - np.einsum("ki,kj->kij", r, r))


@pytest.mark.parametrize("seed", range(6))
def test_point_masses_have_the_mass_properties(seed):
    rng = np.random.default_rng(seed)
    # a physical inertia: that of a random cloud (flat or needle-like for some seeds)
    r = rng.standard_normal((20, 3)) * [1.0, 0.3 if seed % 2 else 1.0, 0.0 if seed > 3 else 1]
    w = rng.uniform(0.1, 1.0, 20)
    r -= w @ r / w.sum()
    mp = MassProperties(float(w.sum()), rng.standard_normal(3), _inertia(w, r))
    x, m = point_masses(mp)
    assert np.isclose(m.sum(), mp.mass, rtol=1e-14)
    np.testing.assert_allclose(m @ x / m.sum(), mp.center_of_mass, atol=1e-14)
    J = _inertia(m, x - mp.center_of_mass)
    np.testing.assert_allclose(J, mp.inertia, atol=1e-12 * np.abs(mp.inertia).max())


@pytest.fixture(scope="module")
def cb(demo_robot):
    arm = build_arm(demo_robot, ArmSpec("cb", mesh_size=0.06, n_modes=10))
    return arm, ffrf_links(arm)


def test_links_reassemble_the_body_mass_matrices(cb):
    arm, links = cb
    for body, link in zip(arm.model.bodies, links, strict=True):
        Mb = body_mass_matrix(link)
        # float32 recovery matrices: agreement to ~1e-8 of the largest entry
        assert np.abs(Mb - body.M).max() < 1e-6 * np.abs(body.M).max(), body.name
        np.testing.assert_array_equal(link.K, body.K[6:, 6:])
