from dataclasses import replace

import numpy as np

from flexarm.robot.formats.rapid import read_rapid
from flexarm.robot.ik_path import TOOL0, ik_path
from flexarm.robot.paths import sample_procedure
from flexarm.studies.compensation.solve.path_ik import batched_path_ik, conf_met

from ..conftest import THESIS


def test_batched_equals_sequential_even_where_conf_cannot_be_met(robot):
    """Path_60's configurations contradict its poses: both solvers go by continuity."""
    mod = read_rapid(THESIS)
    ch = replace(robot.chain, tool=TOOL0)
    for name in ("Path_40", "Path_60"):
        proc = mod.procedures[name]
        path = sample_procedure(proc, step_mm=10)
        confs = np.array([m.to_point.conf for m in proc.motions])
        q = batched_path_ik(ch, path, confs, robot.lower, robot.upper)
        ref = ik_path(ch, path, confs, robot.lower, robot.upper, tool=TOOL0).q
        assert np.abs(q - ref).max() < 1e-9


def test_conf_met_accepts_either_side_of_a_boundary_only(robot):
    ch = robot.chain
    q = np.radians([[10.0, 30, 0, -1e-4, 60, 5], [10.0, 30, 0, -20, 60, 5]])
    assert conf_met(ch, q, [[0, 0, 0, 0], [0, 0, 0, 0]]).tolist() == [True, False]
    assert conf_met(ch, q, [[0, -1, 0, 0], [0, -1, 0, 0]]).tolist() == [True, True]
