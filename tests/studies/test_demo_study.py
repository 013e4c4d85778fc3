"""The demo's accuracy study made from parts computed ahead (:mod:`flexarm.studies.demo_study`):
the two-process demo computes the references in one process and the variants in the other,
then the study only reads them back."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from flexarm.studies import demo_study


def test_the_parts_are_the_study_with_fewer_variants(monkeypatch):
    """Each helper runs the demo's own sweep with only the variants or the Tet10 check left
    out: every part is computed with the options (and so under the cache keys) of the
    study that later reads it."""
    from flexarm.robot import load_robot

    calls = []
    monkeypatch.setattr(demo_study, "run_study",
                        lambda robot, pose, progress=None, **kw: calls.append((pose, kw)))
    robot = load_robot()
    demo_study.study_references(lambda s: None)
    demo_study.study_variants(lambda s: None)
    sweep = demo_study.study_sweep(robot)
    assert calls == [("P1", {**sweep, "modes": (), "couplings": ()}),
                     ("P1", {**sweep, "tet10": False})]
    assert sweep["sizes"] == (robot.options.mesh_size,) and sweep["tet10"]


@pytest.mark.slow  # a full-FE reference with Tet10 elements, meshing the box arm
def test_study_from_parts_computed_ahead_computes_nothing(tmp_path, monkeypatch, box_robot):
    """After the references and the variants, the study solves no full FE model and
    reduces no link again, and it is the study of one uninterrupted run."""
    import flexarm.assembly.build as build
    import flexarm.assembly.full_fe as full_fe
    from flexarm.studies.arm_study import run_study

    monkeypatch.setenv("FLEXARM_CACHE", str(tmp_path / "direct"))
    direct = run_study(box_robot, demo_study.POSE, **demo_study.study_sweep(box_robot))

    # the same tetrahedra (the box arm's links are meshed from STL, not pinned)
    shutil.copytree(tmp_path / "direct" / "tets", tmp_path / "parts" / "tets")
    monkeypatch.setenv("FLEXARM_CACHE", str(tmp_path / "parts"))
    said = []
    demo_study.study_references(said.append, box_robot)
    demo_study.study_variants(said.append, box_robot)
    assert sum("full-FE reference at" in s for s in said) == 2  # Tet4 and Tet10, once each

    def recomputed(*args, **kwargs):
        raise AssertionError("computed again")

    monkeypatch.setattr(full_fe, "full_fe_analysis", recomputed)
    monkeypatch.setattr(build, "reduce_with_stats", recomputed)
    study = demo_study.accuracy_study(tmp_path / "out", said.append, box_robot)
    assert (tmp_path / "out" / "study" / "arm_study.csv").is_file()
    np.testing.assert_allclose(study.reference.freq_hz, direct.reference.freq_hz, rtol=1e-9)
    np.testing.assert_allclose(study.discretisation.p_refined, direct.discretisation.p_refined,
                               rtol=1e-9, atol=1e-12)
    assert [r.label + r.coupling for r in study.rows] == [r.label + r.coupling
                                                          for r in direct.rows]
    for got, want in zip(study.rows, direct.rows, strict=True):
        np.testing.assert_allclose(got.freq_hz, want.freq_hz, rtol=1e-9)
        np.testing.assert_allclose(got.C_diag, want.C_diag, rtol=1e-9)
    lines, figures = demo_study.study_lines(study)
    lower = direct.discretisation.lower
    assert figures["flexible_mesh_error_min_pct"] == pytest.approx(100 * lower)
    assert lines[0].startswith(f"- Accuracy study at P1 vs the full-FE reference "
                               f"({direct.reference.n_dofs} DOF)")
