"""Measured natural frequencies are matched to model modes by frequency, not by number."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.assembly.analyses import natural_frequencies
from flexarm.validation.data.measurements import ModalData
from flexarm.validation.diagnosis.search import diagnose
from flexarm.validation.dynamic.modal import (
    MATCH_WINDOW,
    ModalProblem,
    match_frequencies,
    match_modes,
    model_frequencies,
)
from flexarm.validation.tolerances import tol


def _modal(q, rows):
    """ModalData at one pose 'P1' from (mode number, frequency) rows."""
    q6 = np.zeros(6)
    q6[:len(q)] = q
    return ModalData(poses=["P1"] * len(rows), q=np.tile(q6, (len(rows), 1)),
                     modes=[m for m, _ in rows], freq_hz=[f for _, f in rows])


def test_match_modes_assignment_and_window():
    # listed out of order, one model mode (40 Hz) not measured
    assert match_modes([17.1, 16.2, 7.6], [7.5, 16.0, 17.0, 40.0]).tolist() == [2, 1, 0]
    # two measured modes both nearest to 16.0: one-to-one, least total squared error
    assert match_modes([15.8, 16.3], [7.5, 16.0, 17.0]).tolist() == [1, 2]
    # a spurious 3 Hz line (fixture resonance) is unmatched and takes no model mode away
    assert match_modes([3.0, 7.6], [7.5, 16.0]).tolist() == [-1, 0]
    # without the window the relative error of the 3 Hz line would dominate the sum
    assert match_modes([3.0, 7.6], [7.5, 16.0], window=None).tolist() == [0, 1]
    assert match_modes([], [7.5]).tolist() == []


def test_close_modes_listed_out_of_order(demo):
    """Modes 8 and 9 at P1 are 3 % apart (256 and 265 Hz); the file lists them the other
    way round (the lab's numbering).  Matching by number would compare each with the
    other's model mode (3 %, 6 standard uncertainties of 0.5 %); matching by frequency
    assigns them right."""
    robot, arm = demo
    q = robot.pose("P1")
    F = natural_frequencies(arm, q)
    assert 0.0 < (F[8] - F[7]) / F[7] < 0.05  # the close pair
    noise = 1 + 1e-3 * np.array([1, -1, 2, -2, 1, -1])
    rows = [(1, F[0]), (2, F[1]), (3, F[2]), (4, F[3]), (8, F[8]), (9, F[7])]
    modal = _modal(q, [(m, f * e) for (m, f), e in zip(rows, noise, strict=True)])
    m = match_frequencies(arm, modal)
    assert m.matched.all()
    assert m.model_mode.tolist() == [1, 2, 3, 4, 9, 8]
    assert np.allclose(m.model_hz, [F[0], F[1], F[2], F[3], F[8], F[7]])
    assert np.allclose(model_frequencies(arm, modal), m.model_hz)
    by_number = F[np.asarray(modal.modes) - 1]
    assert np.abs(by_number / modal.freq_hz - 1).max() > 0.025  # what number matching gives
    data = _static(robot, arm)
    pb = ModalProblem(arm, data, modal=modal)
    assert pb.n_modal == 6 and not pb.unmatched
    assert pb.modal_chi2([]) < 1.0  # every frequency within 0.2 % of its model mode


def test_unmatched_measured_mode_reported_and_kept_as_evidence(demo):
    """A measured mode at half the first model frequency: ``compare``'s table reports it
    unmatched; the diagnosis keeps it in the data at the fixed cost ``C^2`` (left out of
    chi^2_red, so the static fit is not spoiled) and names it in the verdict."""
    robot, arm = demo
    q = robot.pose("P1")
    F = natural_frequencies(arm, q)
    spurious = 0.5 * F[0]  # no model mode within a factor 1 + MATCH_WINDOW
    assert F.min() / spurious > 1 + MATCH_WINDOW
    modal = _modal(q, [(1, F[0]), (2, F[1]), (3, spurious)])
    m = match_frequencies(arm, modal)
    assert m.matched.tolist() == [True, True, False]
    assert m.model_mode[:2].tolist() == [1, 2] and np.isfinite(m.model_hz).all()
    (line,) = m.unmatched(modal)
    assert line.startswith(f"pose P1 mode 3: {spurious:.4g} Hz has no model mode within a "
                           "factor 1.5")
    data = _static(robot, arm)
    pb = ModalProblem(arm, data, modal=modal)
    assert pb.n_modal == 3 and pb.n_obs == pb.n_obs_rows() == 3 * 4 + 3
    assert len(pb.wy()) == len(pb.wpredict([]))
    C = tol.pair_window / tol.freq_noise
    assert (pb.wy() - pb.wpredict([]))[-1] == pytest.approx(C)
    assert pb.penalty([]) == (pytest.approx(C**2), 1)
    dg = diagnose(arm, data, modal=modal, heldout=False, max_effects=0)
    assert dg.misfit.missing_modes == (f"the model lacks a mode near {spurious:.4g} Hz at P1",)
    assert dg.unexplained and dg.final.chi2_red < 2.0


def test_too_many_measured_modes(demo):
    robot, arm = demo
    q = robot.pose("P1")
    n = len(natural_frequencies(arm, q))
    modal = _modal(q, [(k + 1, 10.0 * (k + 1)) for k in range(n + 1)])
    with pytest.raises(ValueError, match=f"give {n + 1} modes at pose 'P1'; the model has {n}"):
        match_frequencies(arm, modal)


def _static(robot, arm):
    """A small static data set at P1 (two series of three readings)."""
    from flexarm.validation.data.load_plan import LabPlan, parse_dirs
    from flexarm.validation.lab.virtual_lab import virtual_lab

    plan = LabPlan({"P1": robot.pose("P1")}, np.array([0.0, 400.0, 800.0]), parse_dirs("y,z"))
    return virtual_lab(arm, plan, noise=15e-6, seed=0)
