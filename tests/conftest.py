"""Tiny canonical fixtures shared by the whole test suite.

Everything here is small enough to build in milliseconds; anything bigger belongs in
the test module that needs it (with ``scope="module"``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from flexarm.fe import MATERIALS, Material, TetMesh, select_nodes


@pytest.fixture(scope="session")
def steel() -> Material:
    """E = 210 GPa, nu = 0.3, rho = 7850 kg/m^3."""
    return MATERIALS["steel"]


def _with_ends(mesh: TetMesh) -> TetMesh:
    return mesh.with_node_sets(
        {"fixed": select_nodes(mesh, "x=min"), "tip": select_nodes(mesh, "x=max")}
    )


@pytest.fixture(scope="session")
def two_element_cantilever() -> TetMesh:
    """The smallest cantilever: 2 hexahedral cells (12 Tet4), 1.0 x 0.1 x 0.1 m.

    Node sets ``fixed`` (x = 0) and ``tip`` (x = 1 m).
    """
    return _with_ends(TetMesh.box((1.0, 0.1, 0.1), (2, 1, 1)))


@pytest.fixture(scope="session")
def tet10_bar() -> TetMesh:
    """Tet10 bar 1.0 x 0.1 x 0.1 m, 10 x 2 x 2 cells (1575 DOF), node sets ``fixed``/``tip``.

    Big enough (> ``eigen.DENSE_LIMIT`` free DOFs) that eigen-solves take the
    factorise + ARPACK path, small enough to solve in a fraction of a second.
    """
    return _with_ends(TetMesh.box((1.0, 0.1, 0.1), (10, 2, 2), order=2))


def perturbed_box(order: int = 1, divisions=(3, 3, 3), amplitude: float = 0.3,
                  curved: float = 0.0, seed: int = 0) -> TetMesh:
    """An irregular mesh of the unit cube (boundary nodes stay on the faces).

    Interior corner nodes move by up to ``amplitude`` x cell size (uniform random,
    fixed seed); with ``order=2`` and ``curved > 0`` every mid-edge node (boundary ones
    too) moves by up to ``curved`` x cell size, which curves the element edges.
    Raises if any element comes out inverted.
    """
    rng = np.random.default_rng(seed)
    base = TetMesh.box((1.0, 1.0, 1.0), divisions)
    h = 1.0 / max(divisions)
    pts = base.points.copy()
    inner = np.all((pts > 1e-9) & (pts < 1 - 1e-9), axis=1)
    pts[inner] += rng.uniform(-amplitude * h / 2, amplitude * h / 2, (int(inner.sum()), 3))
    mesh = TetMesh(pts, base.tets).check("perturbed box")
    if order == 2:
        mesh = mesh.to_tet10()
        if curved:
            pts = mesh.points.copy()
            mids = np.arange(base.n_nodes, mesh.n_nodes)
            pts[mids] += rng.uniform(-curved * h / 2, curved * h / 2, (len(mids), 3))
            mesh = TetMesh(pts, mesh.tets)
    return mesh


@pytest.fixture(scope="session")
def make_perturbed_box():
    """The factory :func:`perturbed_box` (for meshes with other seeds or amplitudes)."""
    return perturbed_box


@pytest.fixture(scope="session")
def irregular_tet4() -> TetMesh:
    """Unit cube, 3 x 3 x 3 cells, interior nodes perturbed (seed 0)."""
    return perturbed_box(order=1)


@pytest.fixture(scope="session")
def irregular_tet10() -> TetMesh:
    """Unit cube, 3 x 3 x 3 cells, interior corners perturbed, straight mid-edge nodes."""
    return perturbed_box(order=2)


@pytest.fixture(scope="session")
def curved_tet10() -> TetMesh:
    """As ``irregular_tet10`` with every mid-edge node moved by up to 5 % of the cell."""
    return perturbed_box(order=2, curved=0.1)


def rigid_body_vectors(points: np.ndarray, center=(0.0, 0.0, 0.0)) -> np.ndarray:
    """(3n, 6): unit translations x, y, z then unit rotations about x, y, z at ``center``."""
    r = np.asarray(points, dtype=float) - np.asarray(center, dtype=float)
    n = len(r)
    out = np.zeros((n, 3, 6))
    for i in range(3):
        out[:, i, i] = 1.0
    # rotation about axis k: u = e_k x r
    for k in range(3):
        out[:, :, 3 + k] = np.cross(np.eye(3)[k], r)
    return out.reshape(3 * n, 6)


@pytest.fixture(scope="session")
def make_rigid_body_vectors():
    """The factory :func:`rigid_body_vectors`."""
    return rigid_body_vectors


# ----------------------------------------------------------------- robots
@pytest.fixture(scope="session")
def demo_robot():
    from flexarm.robot.demo_arm import load_demo_robot

    return load_demo_robot()


@pytest.fixture(scope="session")
def demo_emodel(demo_robot):
    """E-model of the demo arm with mass properties of its tetrahedral meshes."""
    from flexarm.assembly.emodel import emodel

    return emodel(demo_robot, method="tets")


def pytest_collection_modifyitems(config, items):
    """Skip ``slow`` tests unless selected with ``-m slow`` (a bare ``pytest`` stays fast)."""
    if "slow" in (config.getoption("-m") or ""):
        return
    skip = pytest.mark.skip(reason="slow: run with -m slow")
    for item in items:
        if "slow" in item.keywords:
            item.add_marker(skip)


@pytest.fixture(scope="session")
def box_robot(tmp_path_factory):
    """The three-link box arm of ``box_arm.py`` (STL + TOML in a temporary folder)."""
    from .box_arm import box_arm_robot

    return box_arm_robot(tmp_path_factory.mktemp("box_arm"))


@pytest.fixture(scope="session")
def flex_arm(demo_robot):
    """CB(10) flexible demo arm on a coarse 60 mm mesh (cached build)."""
    from flexarm.assembly.arm import ArmSpec, build_arm

    return build_arm(demo_robot, ArmSpec("cb", mesh_size=0.06, n_modes=10)).model


@pytest.fixture(scope="session")
def module():
    """The thesis's appendix-B RAPID module (loaded circle test)."""
    from importlib.resources import files

    from flexarm.robot.formats.rapid import read_rapid

    return read_rapid(files("flexarm") / "data" / "rapid" / "ldbb_thesis.mod")


@pytest.fixture()
def figures(monkeypatch):
    """``{png name: Figure}`` of every figure saved while the test runs: a test compares
    what is drawn with the CSV written beside it."""
    import matplotlib.figure

    saved = {}
    real = matplotlib.figure.Figure.savefig

    def savefig(self, fname, *args, **kwargs):
        saved[Path(fname).name] = self
        return real(self, fname, *args, **kwargs)

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", savefig)
    return saved


@pytest.fixture(scope="session")
def gl():
    """The off-screen render backend (PyVista); skips, with the reason, where there is none."""
    from flexarm.fe.errors import FlexarmError, MissingDependencyError
    from flexarm.reduction.render import render_backend

    try:
        return render_backend()
    except (FlexarmError, MissingDependencyError) as exc:
        pytest.skip(f"no off-screen rendering here: {exc}")
