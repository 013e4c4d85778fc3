"""The standalone Exudyn model: the script and its files, copied to another folder, run
in a fresh virtual environment that holds Exudyn and NumPy from the package registry and
neither flexarm nor SciPy, and give the frequencies of ``flexarm modes`` (the same model)
to 1e-6; the assembly file holds the arm's own rigid-body inertia and joint springs."""

import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

from flexarm.assembly.analyses import modes
from flexarm.assembly.arm import ArmSpec, build_arm

pytest.importorskip("exudyn", reason="Exudyn (pip install flexarm[mbs]) writes the link files")

from flexarm.studies.exudyn.model import ffrf_links  # noqa: E402 - after the skip
from flexarm.studies.exudyn.standalone import write_standalone  # noqa: E402

CB = ArmSpec("cb", mesh_size=0.06, n_modes=10)


@pytest.fixture(scope="module")
def written(demo_robot, tmp_path_factory):
    arm = build_arm(demo_robot, CB)
    q = demo_robot.pose("P1")
    paths = write_standalone(tmp_path_factory.mktemp("exudyn") / "arm_exudyn.py", arm, q,
                             "P1", links=ffrf_links(arm))
    return arm, q, paths


def _fresh_venv(folder):
    """A virtual environment without system site-packages, with ``pip install exudyn
    numpy`` (through pip's cache); its python, or a skip naming pip's complaint."""
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(folder)], check=True)
    python = folder / "bin" / "python"
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    res = subprocess.run([sys.executable, "-m", "pip", "--python", str(python), "install",
                          "--disable-pip-version-check", "-q", "exudyn", "numpy"],
                         capture_output=True, text=True, env=env)
    if res.returncode:
        pytest.skip("pip install exudyn numpy failed (no registry?): "
                    + (res.stderr.strip().splitlines() or ["?"])[-1])
    return python, env


def test_script_runs_without_flexarm_in_a_fresh_venv(written, tmp_path):
    arm, q, paths = written
    archive = tmp_path / "archive"  # the model moves as a folder, nothing else
    archive.mkdir()
    for p in paths:
        shutil.copy2(p, archive)
    python, env = _fresh_venv(tmp_path / "venv")
    for missing in ("flexarm", "scipy"):
        res = subprocess.run([str(python), "-I", "-c", f"import {missing}"],
                             capture_output=True, env=env)
        assert res.returncode != 0, f"{missing} is importable in the fresh venv"
    res = subprocess.run([str(python), "-I", str(archive / paths[0].name), "-n", "10"],
                         capture_output=True, text=True, env=env, cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    rows = [r.split() for r in res.stdout.splitlines() if r.strip()[:1].isdigit()]
    f = np.array([float(r[1]) for r in rows])
    assert f.size == 10
    np.testing.assert_allclose(f, modes(arm.model, q).freq_hz[:10], rtol=1e-6)
    assert not (tmp_path / "solution").exists()  # no Exudyn output in the working folder


def test_assembly_file_is_the_arm(written, demo_robot):
    arm, q, paths = written
    names = [p.name for p in paths]
    assert names[:2] == ["arm_exudyn.py", "arm_exudyn.npz"]
    assert len(names) == 2 + sum(b.superelement is not None for b in arm.builds)
    text = paths[0].read_text()
    assert "import flexarm" not in text and "from flexarm" not in text
    with np.load(paths[1]) as d:
        model = arm.model
        rigid = [i for i, f in enumerate(d["link_files"]) if not f]
        assert all(str(f) in names for f in d["link_files"] if f)
        for i in rigid:
            np.testing.assert_allclose(d["mass"][i], model.bodies[i].M[0, 0], rtol=1e-15)
            np.testing.assert_allclose(d["inertia"][i], model.bodies[i].M[3:6, 3:6],
                                       rtol=1e-15)
        k = d["joint_stiffness"][:, 3]  # the joint frame's first rotation: the axis
        np.testing.assert_allclose(k, [jm.stiffness[3] for jm in model.joints], rtol=1e-15)
        np.testing.assert_allclose(d["q"], q, rtol=0, atol=0)
        # the file's frequencies come from the eigenvalues-only driver, these from the one
        # that also returns vectors: equal to round-off, not bit for bit (1e-14 failed
        # once with multi-threaded BLAS at load 5.6)
        np.testing.assert_allclose(d["freq_hz"][:10], modes(model, q).freq_hz[:10], rtol=1e-12)
