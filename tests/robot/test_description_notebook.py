"""Robot (flexarm/robot/description.py) in a notebook: a repr of one short line."""

from __future__ import annotations

import dataclasses

from flexarm.robot import load_robot


def test_repr_is_short_and_states_the_model():
    robot = load_robot()
    text = repr(robot)
    assert len(text) < 300 and "\n" not in text  # the dataclass repr was ~9,500 characters
    opts = robot.options
    assert text.startswith(f"Robot({robot.name!r}, {len(robot.links)} links, "
                           f"{len(robot.joints)} joints, poses ")
    assert all(p in text for p in list(robot.poses)[:4])
    assert (f"mesh {opts.mesh_size * 1e3:.4g} mm Tet{4 if opts.element_order == 1 else 10} "
            f"({opts.mesher}), {opts.cb_modes} CB modes, base {robot.base.kind})") in text


def test_repr_follows_the_options_and_equality_is_unchanged():
    robot = load_robot()
    fine = dataclasses.replace(robot, options=dataclasses.replace(
        robot.options, mesh_size=0.0125, element_order=2, cb_modes=4),
        poses={f"P{k}": robot.poses["P1"] for k in range(9)})
    text = repr(fine)
    assert "mesh 12.5 mm Tet10" in text and "4 CB modes" in text
    assert "poses P0, P1, P2, P3, … (+5)," in text and len(text) < 300
    assert fine == fine and fine != robot  # identity equality (eq=False), as before


def test_full_repr_keys_what_the_short_repr_leaves_out():
    robot = load_robot()
    j2 = robot.joints[1]
    softer = dataclasses.replace(robot, joints=(robot.joints[0], dataclasses.replace(
        j2, model=dataclasses.replace(j2.model, torsion=0.5 * j2.model.torsion)),
        *robot.joints[2:]))
    assert repr(softer) == repr(robot)  # same counts and options: same notebook line
    assert softer.full_repr() != robot.full_repr()  # but a cache key must tell them apart
    assert f"torsion={j2.model.torsion!r}" in robot.full_repr()
