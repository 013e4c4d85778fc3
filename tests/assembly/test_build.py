"""Link build: region order, superelement cache, statistics."""

import numpy as np
import pytest

from flexarm.assembly.build import BuildOptions, build_link, build_robot, link_regions

from ..box_arm import box_mesher


def test_region_order_demo(demo_robot):
    assert link_regions(demo_robot, 0) == ("base", "joint_1")
    assert link_regions(demo_robot, 2) == ("joint_2", "joint_3")
    assert link_regions(demo_robot, 6) == ("joint_6", "tcp")
    assert link_regions(demo_robot, 6, tcp="rigid") == ("joint_6",)


def test_build_and_cache(box_robot, tmp_path, monkeypatch):
    monkeypatch.setenv("FLEXARM_CACHE", str(tmp_path))  # empty, even when the session's is kept
    msgs = []
    opts = BuildOptions("cb", 4)
    first = build_robot(box_robot, opts, mesher=box_mesher, progress=msgs.append)
    assert [lb.regions for lb in first] == [("base", "joint_1"), ("joint_1", "joint_2"),
                                            ("joint_2", "tcp")]
    assert [lb.n_reduced for lb in first] == [16, 16, 16]
    assert first[2].n_fe_dofs == 3 * 9 * 3 * 3 and first[2].n_tets == 6 * 8 * 2 * 2
    assert any("arm" in m for m in msgs)
    again = build_link(box_robot, 2, opts, mesher=box_mesher)
    assert again.is_cached and again.path == first[2].path and again.path.suffix == ".h5"
    np.testing.assert_array_equal(again.superelement.K, first[2].superelement.K)
    # a different input is a different file
    other = build_link(box_robot, 2, BuildOptions("cb", 5), mesher=box_mesher)
    assert not other.is_cached and other.path != first[2].path


def test_fixed_interface_frequencies_increase_with_stiffness(box_robot):
    soft = build_link(box_robot, 2, BuildOptions("cb", 3), mesher=box_mesher, cache=False)
    stiff = build_link(box_robot, 2, BuildOptions("cb", 3, stiffness_scale=4.0),
                       mesher=box_mesher, cache=False)
    np.testing.assert_allclose(stiff.freq_hz, 2 * soft.freq_hz, rtol=1e-8)


def test_bad_options(box_robot):
    with pytest.raises(ValueError, match="method"):
        BuildOptions("svd").resolved(box_robot)
    with pytest.raises(ValueError, match="coupling"):
        BuildOptions(coupling="glue").resolved(box_robot)


def test_gmsh_mesher_builds_reproducibly(box_robot, tmp_path):
    """``model.mesher = "gmsh"``: the same CAD gives the same superelement, bit for bit,
    under its own cache key; the setting survives a TOML round trip."""
    import dataclasses

    pytest.importorskip("gmsh", exc_type=ImportError)
    from flexarm.robot.formats.toml import read, write

    robot = dataclasses.replace(box_robot, options=dataclasses.replace(box_robot.options,
                                                                       mesher="gmsh"))
    opts = BuildOptions("cb", 3)
    a = build_link(robot, 2, opts, cache=False)
    b = build_link(robot, 2, opts, cache=False)
    assert a.n_tets > 0 and a.n_tets == b.n_tets
    np.testing.assert_array_equal(a.superelement.K, b.superelement.K)
    np.testing.assert_array_equal(a.superelement.M, b.superelement.M)
    cached = build_link(robot, 2, opts)
    default = build_link(box_robot, 2, opts, mesher=box_mesher)
    assert cached.path != default.path
    write(tmp_path / "robot.toml", robot)
    assert read(tmp_path / "robot.toml").options.mesher == "gmsh"


def test_unknown_mesher_is_refused(box_robot):
    import dataclasses

    with pytest.raises(ValueError, match="model.mesher must be one of auto, tetwild, gmsh, "
                                         "got 'netgen'"):
        dataclasses.replace(box_robot, options=dataclasses.replace(box_robot.options,
                                                                   mesher="netgen"))
