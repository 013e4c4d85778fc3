"""A robot built with its links meshed in worker processes: the same superelements as one
after the other, a table naming each link's mesher, and reproducible under ``"auto"``."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from flexarm.assembly.build import BuildOptions, robot_build
from flexarm.fe.processes import can_spawn

from ..box_arm import box_mesher
from ..cli_run import run_cli

pytestmark = pytest.mark.skipif(not can_spawn(), reason="no process semaphores here")

OPTS = BuildOptions("cb", 4)


def _auto(robot):
    return dataclasses.replace(robot, options=dataclasses.replace(robot.options, mesher="auto"))


def test_two_processes_build_what_one_builds(box_robot):
    said = []
    parallel = robot_build(box_robot, OPTS, cache=False, mesher=box_mesher, progress=said.append,
                           jobs=2)
    serial = robot_build(box_robot, OPTS, cache=False, mesher=box_mesher, jobs=1)
    assert parallel.jobs == 2 and serial.jobs == 1
    for a, b in zip(parallel.links, serial.links, strict=True):
        assert a.name == b.name and a.mesher == b.mesher == "box_mesher"
        # a worker runs BLAS on one thread, this process on several: the sums are grouped
        # differently, so the two agree to round-off, not bit for bit.  The constraint
        # modes are solves with the interior stiffness, so that round-off grows with its
        # condition number, past the last digit of the largest entry (1.7e-13 of it seen
        # with multi-threaded BLAS)
        for x, y in ((a.superelement.K, b.superelement.K), (a.superelement.M, b.superelement.M)):
            np.testing.assert_allclose(x, y, rtol=0, atol=1e-11 * np.abs(y).max())
    # every link's progress reached this process
    assert all(any(m.startswith(f"{name}: ") for m in said) for name in ("base", "column", "arm"))
    table = parallel.text().splitlines()
    assert table[0].split()[:3] == ["link", "mesher", "tets"]
    assert [row.split()[1] for row in table[1:4]] == ["box_mesher"] * 3
    assert table[-1].startswith("3 links built in") and table[-1].endswith("(on 2 processes)")


def test_auto_builds_are_reproducible_and_name_gmsh(box_robot, tmp_path, monkeypatch):
    """Two builds of the same robot in two empty caches, links meshed side by side."""
    pytest.importorskip("gmsh", exc_type=ImportError)
    robot = _auto(box_robot)
    builds = []
    for folder in ("one", "two"):
        monkeypatch.setenv("FLEXARM_CACHE", str(tmp_path / folder))
        builds.append(robot_build(robot, OPTS, jobs=2))
    first, second = builds
    assert first.is_reproducible and [lb.mesher for lb in first.links] == ["gmsh"] * 3
    for a, b in zip(first.links, second.links, strict=True):
        assert not a.is_cached and not b.is_cached
        np.testing.assert_array_equal(a.freq_hz, b.freq_hz)
        np.testing.assert_array_equal(a.superelement.K, b.superelement.K)
    # warm: nothing to mesh, so no worker process is started
    warm = robot_build(robot, OPTS, jobs=2)
    assert warm.jobs == 1 and all(lb.is_cached for lb in warm.links)
    assert all(lb.mesher == "gmsh" for lb in warm.links)


def test_cli_build_prints_the_table_per_link(box_robot, tmp_path, monkeypatch):
    pytest.importorskip("gmsh", exc_type=ImportError)
    from flexarm.robot.formats.toml import write

    monkeypatch.setenv("FLEXARM_CACHE", str(tmp_path / "cache"))
    toml = tmp_path / "box.toml"
    write(toml, _auto(box_robot))
    code, out, err = run_cli(["build", "--robot", str(toml), "-j", "2", "--modes", "4"])
    assert code == 0, err
    rows = {line.split()[0]: line.split() for line in out.splitlines()[1:4]}
    assert set(rows) == {"base", "column", "arm"} and {r[1] for r in rows.values()} == {"gmsh"}
    assert "3 links built in" in out and "(on 2 processes)" in out
    code, out, err = run_cli(["build", "--robot", str(toml), "-j", "0"])
    assert code == 2 and "--jobs" in err
