"""E-model of the demo arm: mass properties and its reference figures (DESIGN §4).

``python -m pytest tests/assembly/test_emodel.py -s -m slow`` prints the figures with
the mass properties of the links' tetrahedral meshes (the default run uses the CAD
surfaces, whose volume integrals agree to < 0.1 %; see ``test_tet_vs_surface_mass``).
"""

import numpy as np
import pytest

from flexarm.assembly.analyses import (
    diagonal_compliance,
    frf,
    gravity_sag,
    identify_stiffness,
    modes,
    tcp_compliance,
)
from flexarm.assembly.emodel import emodel, link_mass_properties
from flexarm.assembly.maps import stiffness_map


def acceptance_figures(robot, arm, n_grid=100):
    q1, q2 = robot.pose("P1"), robot.pose("P2")
    C1 = tcp_compliance(arm, q1)
    lo, hi = robot.lower, robot.upper
    m = stiffness_map(arm, q1, np.linspace(lo[1], hi[1], n_grid), np.linspace(lo[2], hi[2], n_grid),
                      frequencies=False)
    return {
        "defl_y_mm_800N_P1": 800 * C1[1, 1] * 1e3,
        "least_stiff_P1": "xyz"[int(np.argmax(np.diag(C1)[:3]))],
        "f1_P1_Hz": modes(arm, q1).freq_hz[0],
        "f1_P2_Hz": modes(arm, q2).freq_hz[0],
        "f1_P3_Hz": modes(arm, robot.pose("P3")).freq_hz[0],
        "y_least_stiff_grid_share": float(np.mean(m.least_stiff == 1)),
    }


def check_figures(fig):
    shown = {k: (round(v, 3) if isinstance(v, float) else v) for k, v in fig.items()}
    print("\nE-model reference figures:", shown)  # noqa: T201
    assert 5.0 <= fig["defl_y_mm_800N_P1"] <= 7.0
    assert fig["least_stiff_P1"] == "y"
    assert 6.0 <= fig["f1_P1_Hz"] <= 12.0
    assert fig["f1_P2_Hz"] > 10.0
    assert fig["y_least_stiff_grid_share"] >= 0.9


def test_acceptance_figures_surface(demo_robot):
    check_figures(acceptance_figures(demo_robot, emodel(demo_robot, method="surface")))


@pytest.mark.slow
def test_acceptance_figures_tets(demo_robot, demo_emodel):
    check_figures(acceptance_figures(demo_robot, demo_emodel))
    total = sum(b.M[0, 0] for b in demo_emodel.bodies)
    print(f"total mass from tet meshes: {total:.1f} kg")  # noqa: T201
    assert total == pytest.approx(425, rel=0.03)


@pytest.mark.parametrize("index", [6])
def test_tet_mass_properties_equal_boundary_surface(demo_robot, index):
    """Acceptance: tet-mesh mass properties == trimesh of the tet mesh's own boundary."""
    import trimesh

    from flexarm.fe.mass_properties import mass_properties
    from flexarm.meshes import load_surface, tetrahedralize

    lk = demo_robot.links[index]
    tets = tetrahedralize(load_surface(lk.mesh, units=lk.units), 0.04, name=lk.name)
    rho = lk.material.rho
    mp = mass_properties(tets, rho)
    faces = tets.boundary_faces()
    surf = trimesh.Trimesh(tets.points, faces, process=False)
    tm = surf.mass_properties
    assert abs(rho * tm.volume - mp.mass) < 1e-8 * mp.mass
    assert np.abs(tm.center_mass - mp.center_of_mass).max() < 1e-8
    assert np.abs(rho * tm.inertia - mp.inertia).max() < 1e-8 * np.abs(mp.inertia).max()
    # and the tet mesh fills the CAD solid (the volume integrals agree to 0.5 %)
    cad = link_mass_properties(lk, method="surface")
    lumped = sum(m.mass for m in lk.lumped)
    assert mp.mass == pytest.approx(cad.mass - lumped, rel=5e-3)


def test_p1_analyses(demo_robot):
    arm = emodel(demo_robot, method="surface")
    q = demo_robot.pose("P1")
    C = tcp_compliance(arm, q)
    assert np.allclose(C, C.T) and np.all(np.linalg.eigvalsh(C[:3, :3]) > 0)
    # identification from three load cases recovers the model's stiffness (eq. 3.12)
    F = np.array([[800.0, 0, 0], [300.0, 700.0, 0], [0, 200.0, 800.0]])
    rep = identify_stiffness(arm, q, F)
    assert np.allclose(rep.K_full, np.linalg.inv(C[:3, :3]), rtol=1e-9)
    assert rep.error_full.max() < 1e-9 and rep.error_diag.max() > 1e-3
    assert np.allclose(diagonal_compliance(C), np.diag(np.diag(C)[:3]))
    # FRF: static gain equals the compliance; a resonance peak at the first mode
    md = modes(arm, q)
    H = frf(arm, q, [0.0, md.freq_hz[0]])
    assert np.allclose(H[0].real, C, rtol=1e-9, atol=1e-15)
    assert abs(H[1, 1, 1]) > 5 * C[1, 1]
    assert np.all((md.damping > 0) & (md.damping < 0.1))
    assert np.allclose(md.energy.sum(axis=0), 1.0)
    # gravity: the TCP sags down; doubling g doubles the sag (linear)
    sag = gravity_sag(arm, q)
    assert sag[2] < 0
    assert np.allclose(gravity_sag(arm, q, [0, 0, -2 * 9.80665]), 2 * sag)


def test_mode_shapes_deterministic(demo_robot):
    arm = emodel(demo_robot, method="surface")
    a, b = modes(arm, demo_robot.pose("P3")), modes(arm, demo_robot.pose("P3"))
    assert np.array_equal(a.shapes, b.shapes) and np.all(np.diff(a.freq_hz) > 0)
    # mass-normalised: Phi^T M Phi = I
    from flexarm.assembly.system import system_matrices

    M = system_matrices(arm, demo_robot.pose("P3")).M
    assert np.allclose(a.shapes.T @ M @ a.shapes, np.eye(len(a.freq_hz)), atol=1e-9)
