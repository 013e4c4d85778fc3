"""The PETSc/SLEPc backend under ``mpiexec`` equals the default (in-core) path.

``bash install.sh --test`` (or ``--mpi``) sets up ``.venv/mpi``: Debian's petsc4py /
slepc4py / mpi4py with flexarm editable on top.  These tests launch the real command,
``mpiexec -n N .venv/mpi/bin/flexarm reduce ... --backend petsc``, on a small Tet10 link
with randomly displaced nodes (no symmetry, so no repeated frequencies), and compare the
superelement it writes with the one :func:`reduce_with_stats` gives here.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from reduction_helpers import STEEL, rel

import flexarm
from flexarm.fe import TetMesh
from flexarm.fe.solvers import available_backends
from flexarm.reduction import formats, reduce_with_stats
from flexarm.reduction.interfaces import parse_cylinder

ROOT = Path(flexarm.__file__).resolve().parent.parent
VENV_PYTHON = Path(os.environ.get("FLEXARM_MPI_PYTHON", ROOT / ".venv" / "mpi" / "bin" / "python"))
SIZE = (0.5, 0.08, 0.05)
CYLINDERS = ("a:0,0.04,0.025,1,0,0,0.1,1e-6", "b:0.5,0.04,0.025,1,0,0,0.1,1e-6")
REGIONS = [parse_cylinder(c) for c in CYLINDERS]  # as the command parses them


def _mpi_env() -> dict:
    env = dict(os.environ)
    if os.geteuid() == 0:  # CI runs as root; Open MPI refuses that unless told
        env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    env.setdefault("OMPI_MCA_rmaps_base_oversubscribe", "1")  # 3 ranks on 2 cores
    return env


def _mpi_unavailable() -> str | None:
    """Why the MPI backend cannot run here, or None."""
    if shutil.which("mpiexec") is None:
        return "mpiexec not found (bash install.sh --mpi installs Open MPI)"
    if not VENV_PYTHON.exists():
        return f"{VENV_PYTHON} missing (bash install.sh --mpi creates it)"
    probe = subprocess.run(
        [str(VENV_PYTHON), "-c", "import petsc4py, slepc4py, mpi4py, flexarm; "
         "print(flexarm.__file__)"], capture_output=True, text=True, env=_mpi_env())
    if probe.returncode != 0:
        return f"{VENV_PYTHON} cannot import petsc4py/slepc4py/mpi4py: " \
               f"{probe.stderr.strip().splitlines()[-1:]}"
    if Path(probe.stdout.strip()).resolve().parent != Path(flexarm.__file__).resolve().parent:
        return f"{VENV_PYTHON} runs another flexarm ({probe.stdout.strip()})"
    return None


pytestmark = pytest.mark.skipif(bool(_reason := _mpi_unavailable()), reason=_reason or "")


@pytest.fixture(scope="module")
def link(tmp_path_factory):
    """Tet10 block 0.5 x 0.08 x 0.05 m, 10 x 3 x 2 cells, interior corners displaced
    by up to 15 % of a cell (fixed seed), as a mesh file and a mesh."""
    box = TetMesh.box(SIZE, (10, 3, 2), order=1)
    rng = np.random.default_rng(7)
    pts = box.points.copy()
    inner = np.all((pts > 1e-9) & (pts < np.array(SIZE) - 1e-9), axis=1)
    pts[inner] += rng.uniform(-0.0025, 0.0025, (int(inner.sum()), 3))
    mesh = TetMesh(pts, box.tets).to_tet10()
    path = tmp_path_factory.mktemp("petsc") / "link.npz"
    from flexarm.meshes import write_volume_mesh

    write_volume_mesh(path, mesh)
    return path, mesh


def _petsc_reduce(mesh_path: Path, out: Path, ranks: int, *options: str):
    flexarm_exe = VENV_PYTHON.parent / "flexarm"
    cmd = ["mpiexec", "-n", str(ranks), str(flexarm_exe), "reduce", str(mesh_path),
           *[a for c in CYLINDERS for a in ("--interface", c)], *options,
           "--backend", "petsc", "-o", str(out)]
    run = subprocess.run(cmd, capture_output=True, text=True, env=_mpi_env(), timeout=300)
    assert run.returncode == 0, run.stderr
    assert run.stdout.count("wrote ") == 1  # rank 0 writes, the others stay silent
    return formats.read(out)


@pytest.mark.parametrize("coupling, method, ranks", [("rbe2", "cb", 2), ("rbe3", "cb", 3),
                                                     ("rbe2", "guyan", 2)])
def test_mpi_reduction_equals_default_path(link, tmp_path, coupling, method, ranks):
    mesh_path, mesh = link
    n_modes = 12
    se = _petsc_reduce(mesh_path, tmp_path / "p.h5", ranks, "--coupling", coupling,
                       "--method", method, "--modes", str(n_modes))
    backend = "pardiso" if "pardiso" in available_backends() else None
    ref, _ = reduce_with_stats(mesh, STEEL, REGIONS, coupling, method, n_modes,
                               backend=backend)
    assert se.K.shape == ref.K.shape == (12 + (n_modes if method == "cb" else 0),) * 2
    assert rel(se.K, ref.K) < 1e-9
    assert rel(se.M, ref.M) < 1e-9
    if method == "cb":
        assert np.abs(se.freq_hz / ref.freq_hz - 1).max() < 1e-10
        assert np.all(np.diff(se.freq_hz) > 0)
    # recovery matrix, stored as float32 by both paths
    assert rel(se.T, ref.T) < 1e-6
    assert se.mass == pytest.approx(ref.mass, rel=1e-12)
    assert se.input_hash == ref.input_hash


def test_mpi_reduction_diagonal_modal_block(link, tmp_path):
    mesh_path, mesh = link
    se = _petsc_reduce(mesh_path, tmp_path / "d.h5", 2, "--modes", "6", "--diagonal")
    b = 12
    assert np.array_equal(se.M[b:, b:], np.eye(6))
    assert np.array_equal(se.K[b:, :b], np.zeros((6, b)))
    omega2 = (2 * np.pi * se.freq_hz) ** 2
    assert np.allclose(np.diag(se.K[b:, b:]), omega2, rtol=1e-12)
