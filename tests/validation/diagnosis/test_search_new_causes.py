"""Causes outside the joint library, each found by its own signature on the demo arm
(static P1-P3 x +-X+-Y+-Z, 0-800 N, 15 µm; 6 modes at each pose, 0.3 %), and the checks
that keep them from absorbing other misfits.

* an added mass on a link: frequencies fall, statics unchanged;
* a load cell that reads high: one common factor between the static compliances and the
  dynamic stiffness;
* a measurement point off the TCP: a lever-arm term in the load-induced rotation;
* a foundation compliant about one base axis only;
* a channel of the shape file mounted the wrong way round.

The fast tests run one seed each; ``-m slow`` sweeps 20 seeds on the imported IRB 4600
(``test_new_causes_irb4600.py``).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from flexarm.robot.effects import parse_effect
from flexarm.validation.diagnosis.search import diagnose
from flexarm.validation.dynamic.compare_shapes import compare_shapes
from flexarm.validation.dynamic.mac import moving_points, pair_modes, reversed_channels
from flexarm.validation.dynamic.shape_fit import ShapeProblem
from flexarm.validation.dynamic.shapes import default_points
from flexarm.validation.lab.modal_lab import virtual_modal, virtual_shapes
from flexarm.validation.tolerances import tol

from ..helpers import PERTURB
from .test_apply_round_trip import assert_round_trip

SIGMA, FREQ_NOISE = 15e-6, 0.003


def _modal(demo, hidden, seed):
    robot, arm = demo
    eff = ([parse_effect(f"stiffness:j{j + 1}={s}") for j, s in enumerate(PERTURB)]
           + [parse_effect(h) for h in hidden])
    poses = {p: robot.pose(p) for p in ("P1", "P2", "P3")}
    return virtual_modal(arm, poses, eff, n_modes=6, freq_noise=FREQ_NOISE, seed=seed)


#: hidden effect -> (accepted kind, parameter, truth [SI], relative tolerance)
CASES = {
    "mass:l3=25kg": ("mass", "mass", 25.0, 0.05),
    "loadcell:s=0.04": ("loadcell", "scale", 0.04, 0.1),
    "reflector:ox=40mm,oz=-20mm": ("reflector", "ox", 0.04, 0.25),
    "foundation:kx=2e7": ("foundation", "cx", 5e-8, 0.05),
}


@pytest.mark.parametrize("hidden", sorted(CASES))
def test_a_cause_outside_the_joint_library_is_named_first(demo, lab, hidden, tmp_path):
    """... and ``diagnose --apply`` writes it: the file gives the final model back."""
    kind, param, truth, rel = CASES[hidden]
    robot, arm = demo
    data = lab([hidden], seed=1)
    dg = diagnose(arm, data, SIGMA, modal=_modal(demo, [hidden], 1), freq_noise=FREQ_NOISE,
                  heldout=False)
    assert [e.kind for e in dg.accepted] == [kind], dg.text()
    assert dg.accepted[0].get(param) == pytest.approx(truth, rel=rel)
    assert_round_trip(robot, arm, data, dg, {p: robot.pose(p) for p in ("P1", "P2", "P3")},
                      tmp_path)
    assert not dg.unexplained


def test_the_new_causes_need_the_vibration_data_they_are_told_by(demo, lab):
    """Without modal data a load cell reading 4 % high is all joint compliances scaled
    alike, and an added mass does not move the statics: neither is a candidate, and
    nothing is accepted in their place."""
    robot, arm = demo
    for hidden in ("loadcell:s=0.04", "mass:l3=25kg"):
        dg = diagnose(arm, lab([hidden], seed=1), SIGMA, heldout=False)
        names = {c.name for c in dg.steps[0].candidates}
        assert "loadcell" not in names and "mass_l3" not in names
        assert not dg.accepted, dg.text()


def test_a_reversed_channel_is_named_and_turned(demo, lab):
    """Channel node 601 y of the shape file reversed (a sensor mounted the wrong way
    round): ``compare`` names it, and the diagnosis names it, turns it and finds no
    effect for it; the same data with the channel right explain the model."""
    robot, arm = demo
    eff = [parse_effect(f"stiffness:j{j + 1}={s}") for j, s in enumerate(PERTURB)]
    poses = {p: robot.pose(p) for p in ("P1", "P2", "P3")}
    pts = default_points(robot)
    shapes = virtual_shapes(arm, poses, pts, eff, n_modes=6, shape_noise=0.02, seed=2)
    i = next(k for k, (n, d) in enumerate(zip(shapes.nodes, shapes.dirs, strict=True))
             if n == 601 and d == "y")
    S = np.array(shapes.shapes)
    S[:, i] *= -1
    flipped = replace(shapes, shapes=S)
    (line,) = compare_shapes(arm, flipped, pts).reversed_channels()
    assert line.startswith("channel node 601 y looks reversed")
    assert not compare_shapes(arm, shapes, pts).reversed_channels()
    data = lab([], seed=2)
    dg = diagnose(arm, data, SIGMA, modal=flipped, points=pts, heldout=False)
    assert not dg.accepted
    assert [c.split(":")[0] for c in dg.misfit.channels] == ["channel node 601 y looks reversed"]
    assert dg.misfit.structures == ("reversed_channel",)
    right = diagnose(arm, data, SIGMA, modal=shapes, points=pts, heldout=False)
    assert not right.accepted and not right.unexplained


def test_a_channel_that_carries_little_of_each_shape_is_found_too(demo, lab):
    """Every channel that moves (10 % of the most-moving one), turned in its turn, is the
    one channel the diagnosis names, and none is named unturned; a mean-MAC gain of 0.05
    (blind to the noise) misses the channels near the base, whose flip moves the mean MAC
    by less but the shape chi-square by far more than the noise."""
    robot, arm = demo
    eff = [parse_effect(f"stiffness:j{j + 1}={s}") for j, s in enumerate(PERTURB)]
    poses = {p: robot.pose(p) for p in ("P1", "P2", "P3")}
    pts = default_points(robot)
    shapes = virtual_shapes(arm, poses, pts, eff, n_modes=6, shape_noise=0.02, seed=3)
    data = lab([], seed=3)

    def problem(s):
        return ShapeProblem(arm, data, SIGMA, "shared", None, s, tol.freq_noise, pts)

    right = problem(shapes)
    assert not right.reversed_channels(right.start_effects)
    moving = np.flatnonzero(moving_points(shapes.shapes, np.arange(shapes.n_dofs), 0.1))
    missed_by_mean_mac = 0
    for i in moving:
        S = np.array(shapes.shapes)
        S[:, i] *= -1
        p = problem(replace(shapes, shapes=S))
        assert [c for c, _ in p.reversed_channels(p.start_effects)] == [i], shapes.dofs[i]
        missed_by_mean_mac += not reversed_channels(S, shapes.shapes)
    assert missed_by_mean_mac >= 10  # 13 of the 32 moving channels on this seed


def test_shapes_alike_at_a_tenfold_frequency_never_pair():
    """A measured 160 Hz mode and a model mode at 1811 Hz with MAC 0.957 are not the same
    mode; within the window the same MAC pairs."""
    p = pair_modes(np.array([[0.957, 0.1]]), [160.0], [1811.0, 150.0])
    assert p.model.tolist() == [-1]
    p = pair_modes(np.array([[0.957, 0.1]]), [160.0], [170.0, 150.0])
    assert p.model.tolist() == [0]
