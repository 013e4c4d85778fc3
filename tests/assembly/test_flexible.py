"""Flexible arm: superelements as bodies; the rigid-link limit equals the E-model."""

import numpy as np
import pytest

from flexarm.assembly.analyses import (
    frf,
    gravity_sag,
    modes,
    natural_frequencies,
    tcp_compliance,
)
from flexarm.assembly.build import BuildOptions
from flexarm.assembly.emodel import emodel
from flexarm.assembly.flexible import flexible_arm
from flexarm.assembly.maps import stiffness_map

from ..box_arm import box_mesher


@pytest.fixture(scope="module")
def box_flex(box_robot):
    return flexible_arm(box_robot, BuildOptions("cb", 6), mesher=box_mesher)


@pytest.mark.parametrize("method", ["cb", "guyan"])
def test_rigid_limit_equals_emodel(box_robot, method):
    """E x 1e6: frequencies and TCP compliance of the E-model to 1e-5."""
    stiff = flexible_arm(box_robot, BuildOptions(method, 6, stiffness_scale=1e6),
                         mesher=box_mesher)
    rigid = emodel(box_robot, method="surface")  # box STL = the structured tet mesh
    for pose in ("P1", "P2"):
        q = box_robot.pose(pose)
        fe = natural_frequencies(rigid, q)
        ff = natural_frequencies(stiff, q)[: len(fe)]
        np.testing.assert_allclose(ff, fe, rtol=1e-5)
        Ce, Cf = tcp_compliance(rigid, q), tcp_compliance(stiff, q)
        assert np.abs(Cf - Ce).max() < 1e-5 * np.abs(Ce).max()


def test_flexible_links_add_compliance(box_robot, box_flex):
    q = box_robot.pose("P1")
    rigid = emodel(box_robot, method="surface")
    Ce, Cf = np.diag(tcp_compliance(rigid, q))[:3], np.diag(tcp_compliance(box_flex, q))[:3]
    assert np.all(Cf > 1.05 * Ce)
    fe, ff = natural_frequencies(rigid, q), natural_frequencies(box_flex, q)
    assert np.all(ff[: len(fe)] < fe)


def test_batched_and_analyses(box_robot, box_flex):
    qs = np.radians([[0, 30], [40, -20], [10, 60]])
    f = natural_frequencies(box_flex, qs)
    C = tcp_compliance(box_flex, qs)
    for k, q in enumerate(qs):
        np.testing.assert_allclose(f[k], natural_frequencies(box_flex, q), rtol=1e-10)
        np.testing.assert_allclose(C[k], tcp_compliance(box_flex, q), rtol=1e-10, atol=1e-20)
    H0 = frf(box_flex, qs[0], [0.0])[0].real
    np.testing.assert_allclose(H0, C[0], rtol=1e-6, atol=1e-6 * np.abs(C[0]).max())
    md = modes(box_flex, qs[0])
    assert np.all((md.damping > 0.005) & (md.damping < 0.03))
    sag = gravity_sag(box_flex, qs)
    assert sag.shape == (3, 6) and np.all(sag[:, 2] < 0)  # the tip drops
    m = stiffness_map(box_flex, qs[0], np.radians([-10, 10]), np.radians([0, 30]),
                      joints=(0, 1), frequencies=True)
    q00 = np.radians([-10.0, 0.0])
    np.testing.assert_allclose(m.freq_hz[0, 0], natural_frequencies(box_flex, q00)[0], rtol=1e-9)
    np.testing.assert_allclose(m.stiffness[0, 0], 1 / np.diag(tcp_compliance(box_flex, q00))[:3],
                               rtol=1e-9)
    assert np.all(np.isfinite(m.least_stiff))


def test_rigid_limit_gravity_sag(box_robot):
    """Same mass properties: the rigid-limit gravity sag equals the E-model's."""
    stiff = flexible_arm(box_robot, BuildOptions("guyan", stiffness_scale=1e6),
                         mesher=box_mesher)
    q = box_robot.pose("P1")
    s_e = gravity_sag(emodel(box_robot, method="surface"), q)
    s_f = gravity_sag(stiff, q)
    assert np.abs(s_f - s_e).max() < 1e-5 * np.abs(s_e).max()


@pytest.mark.slow
def test_rigid_limit_demo(demo_robot):
    """The demo arm (40 mm Tet4): rigid limit == E-model with the *bearing-only* joints."""
    opts = BuildOptions("cb", 6, mesh_size=0.04, stiffness_scale=1e6)
    stiff = flexible_arm(demo_robot, opts)
    rigid = emodel(demo_robot, "tets", 0.04, equivalent=False)
    for pose in ("P1", "P2", "P3"):
        q = demo_robot.pose(pose)
        fe = natural_frequencies(rigid, q)
        # K spans ~1e5..1e17 here: natural_frequencies solves in inverse form
        np.testing.assert_allclose(natural_frequencies(stiff, q)[: len(fe)], fe, rtol=1e-5)
        np.testing.assert_allclose(modes(stiff, q).freq_hz[: len(fe)], fe, rtol=1e-5)
        Ce, Cf = tcp_compliance(rigid, q), tcp_compliance(stiff, q)
        assert np.abs(Cf - Ce).max() < 1e-5 * np.abs(Ce).max()


@pytest.mark.slow
@pytest.mark.parametrize("mesh_size", [0.03, 0.04])
def test_demo_flexible_figures(demo_robot, mesh_size):
    """The flexible demo arm (CB) lands in the same bands as the E-model."""
    from .test_emodel import acceptance_figures, check_figures

    arm = flexible_arm(demo_robot, BuildOptions("cb", mesh_size=mesh_size))
    check_figures(acceptance_figures(demo_robot, arm))
