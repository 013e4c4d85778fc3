"""``compensate`` end to end: the written module read back by ``read_rapid``."""

import numpy as np
import pytest

from flexarm.robot.formats.rapid import read_rapid
from flexarm.robot.ik_path import target_frames
from flexarm.robot.paths import sample_procedure
from flexarm.studies.compensation import compensate
from flexarm.studies.compensation.solve.ik_batch import pose_errors

from .conftest import MILLING, THESIS

PROCS = ["Path_30", "Path_40", "Path_50"]


@pytest.fixture(scope="module")
def circles(robot, arm, tmp_path_factory):
    res = compensate(THESIS, robot, "ballbar:800N", procs=PROCS, arm=arm, step_mm=4)
    path = tmp_path_factory.mktemp("comp") / "compensated.mod"
    res.write_module(path)
    return res, read_rapid(THESIS), read_rapid(path), path


def test_the_unloaded_path_moves_by_exactly_the_predicted_offsets(circles):
    res, orig, back, _ = circles
    shift = {s.name: s.shift for s in res.shifts}
    assert sorted(shift) == sorted(t.name for p in PROCS for m in orig.procedures[p].motions
                                   for t in m.targets)
    for name in PROCS:
        a = sample_procedure(orig.procedures[name], step_mm=5)
        b = sample_procedure(back.procedures[name], step_mm=5)
        ends_a = np.flatnonzero(np.r_[a.segments[1:] != a.segments[:-1], True])
        ends_b = np.flatnonzero(np.r_[b.segments[1:] != b.segments[:-1], True])
        Ta = target_frames(a.points_mm[ends_a], a.quats[ends_a])
        Tb = target_frames(b.points_mm[ends_b], b.quats[ends_b])
        names = [m.to_point.name for m in orig.procedures[name].motions]
        want = np.array([shift[n] for n in names])
        assert np.abs(pose_errors(Ta, Tb) - want).max() < 1e-9
        # and by nothing else: the circle points too
        for m_a, m_b in zip(orig.procedures[name].motions, back.procedures[name].motions,
                            strict=True):
            for ta, tb in zip(m_a.targets, m_b.targets, strict=True):
                d = pose_errors(target_frames(ta.pos_mm, ta.quat), target_frames(tb.pos_mm,
                                                                                  tb.quat))[0]
                assert np.abs(d - shift[ta.name]).max() < 1e-9


def test_structure_speeds_zones_and_configurations_are_unchanged(circles):
    res, orig, back, path = circles
    assert list(back.procedures) == list(orig.procedures) and list(back.targets) == list(
        orig.targets)
    header = 3
    for name, proc in orig.procedures.items():
        for a, b in zip(proc.motions, back.procedures[name].motions, strict=True):
            assert (a.kind, a.speed, a.zone, a.tool, a.wobj, a.options) == (
                b.kind, b.speed, b.zone, b.tool, b.wobj, b.options)
            assert [t.name for t in a.targets] == [t.name for t in b.targets]
            assert b.line == a.line + header
    for name, t in orig.targets.items():
        u = back.targets[name]
        assert np.array_equal(t.conf, u.conf) and np.array_equal(t.extax, u.extax)
        if name not in {s.name for s in res.shifts}:
            assert np.array_equal(t.pos_mm, u.pos_mm) and np.array_equal(t.quat, u.quat)
    # every other line of the file as written, comments included
    old = THESIS.read_text().splitlines()
    new = path.read_text().splitlines()
    assert new[0] == old[0] and new[1].startswith("    ! flexarm compensate:")
    shifted = {s.name for s in res.shifts}
    keep = [x for x in old if not any(f"robtarget {n}:" in x for n in shifted)]
    assert [x for x in new[1 + header:] if not any(f"robtarget {n}:" in x for n in shifted)] \
        == keep[1:]


def test_prediction_and_text(circles):
    res = circles[0]
    for b, a in zip(res.runs_before, res.runs_after, strict=True):
        assert b.circle is not None and 1e-3 < b.rms() < 3e-3
        assert a.rms() < 0.4 * b.rms()  # four targets per turn: the arcs cannot follow
    assert max(np.abs(s.after).max() for s in res.shifts) < 1e-12
    text = res.text()
    assert text.splitlines()[0].startswith("15 targets shifted (largest 2.7")
    assert "between the targets the compensated path keeps" in text  # a limit, with the cure
    assert "--split 30 mm" in text


def test_split_follows_the_deflection_along_the_motions(robot, arm):
    res = compensate(THESIS, robot, "ballbar:800N", procs=["Path_30"], arm=arm, step_mm=4,
                     split_mm=30)
    (b,), (a,) = res.runs_before, res.runs_after
    assert a.rms() < 1e-3 * b.rms() and res.split_mm == 30
    assert res.module_text.count("MoveC Target_90_") == 17  # 486.9 mm in 28.6 mm arcs


def test_shared_targets_expressions_and_the_tool(robot, arm, tmp_path):
    """Path_10 and Path_20 share targets under different bar pivots; an Offs target is
    left alone; the milling module's spindle is the tool."""
    text = THESIS.read_text().replace("MoveL Target_60,v1000,z100",
                                      "MoveL Offs(Target_60,0,0,10),v1000,z100")
    path = tmp_path / "t.mod"
    path.write_text(text)
    res = compensate(path, robot, "ballbar:400N", procs=["Path_10", "Path_20"], arm=arm,
                     step_mm=5)
    notes = "\n".join(res.notes)
    assert "Path_20: target 'Offs(Target_60 , 0 , 0 , 10)' (line 67) is an expression" in notes
    assert "Target_40 is used by Path_10, Path_20 with loads asking for shifts" in notes
    mill = compensate(MILLING, robot, "tool:fx=300", arm=arm, step_mm=4)
    assert [s.name for s in mill.shifts][:2] == ["mill_10", "mill_20"]
    assert max(r.peak for r in mill.runs_after) < 0.05 * max(r.peak for r in mill.runs_before)


def test_bad_force_is_refused_before_reading(robot):
    with pytest.raises(ValueError, match="give the process force"):
        compensate(THESIS, robot)
