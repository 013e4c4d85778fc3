"""Whole-arm accuracy study on the coarse box arm."""

import csv

import numpy as np
import pytest

from flexarm.fe.mesh import TetMesh
from flexarm.studies.arm_study import (
    parse_representation,
    run_study,
    verdict,
)

from ..box_arm import BOXES

SIZES = (0.1, 0.05)
MODES = (0, 4, 12)
COUPLINGS = ("rbe2", "k4")


def sized_box_mesher(link, mesh_size, order):
    """Structured box mesh with about ``mesh_size`` edges (halving it nests the grids)."""
    size, lo, _ = BOXES[link.name]
    div = tuple(max(2, int(round(s / mesh_size))) for s in size)
    return TetMesh.box(size, div, order=order, origin=lo)


@pytest.fixture(scope="module")
def study(box_robot, tmp_path_factory):
    out = tmp_path_factory.mktemp("study")
    lines = []
    res = run_study(box_robot, "P1", SIZES, MODES, COUPLINGS, out, progress=lines.append,
                    mesher=sized_box_mesher)
    return res, out, lines


def _rows(res, size, coupling):
    return sorted((r for r in res.rows if r.mesh_size == size and r.coupling == coupling),
                  key=lambda r: r.n_modes)


def test_parse_representation():
    assert parse_representation("RBE3") == ("rbe3", None)
    assert parse_representation("k8") == ("nodes", 8)
    for bad in ("k2", "rbe4", "kx"):
        with pytest.raises(ValueError, match="rbe2, rbe3 or k<N>"):
            parse_representation(bad)


def test_study_files(study):
    res, out, lines = study
    names = ["arm_study.csv", "arm_study_error_vs_dof.png", "arm_study_pareto.png",
             "arm_study_verdict.txt"]
    assert sorted(p.name for p in res.files) == sorted(names)
    for n in names:
        assert (out / n).stat().st_size > 0
    with open(out / "arm_study.csv") as fh:
        table = list(csv.DictReader(fh))
    n_var = len(SIZES) * len(MODES) * len(COUPLINGS)
    assert len(table) == n_var + 1 and table[0]["label"] == "full-FE"
    assert float(table[0]["f1_Hz"]) == pytest.approx(res.reference.freq_hz[0])
    assert len([s for s in lines if s.startswith("[")]) == n_var  # progress per variant
    text = (out / "arm_study_verdict.txt").read_text()
    assert "within 1%" in text and "within 0.1%" in text


def test_study_numbers_are_physical(study):
    res, _, _ = study
    fine, coarse = min(SIZES), max(SIZES)
    # same mesh and coupling as the reference: Rayleigh-Ritz from above, monotone in n
    rows = _rows(res, fine, "rbe2")
    errs = [r.freq_err_max for r in rows]
    assert all(a >= b - 1e-12 for a, b in zip(errs, errs[1:], strict=False))
    for r in rows:
        assert np.all(np.asarray(r.freq_hz) >= res.reference.freq_hz * (1 - 1e-9))
        assert r.C_err_max < 1e-8  # static condensation is exact at the interfaces
    assert rows[-1].freq_err_max < 5e-3 and rows[0].freq_err_max > 10 * rows[-1].freq_err_max
    for c in COUPLINGS:  # CB no worse than Guyan on its own mesh, coarse mesh worse
        for h in SIZES:
            g, *cb = _rows(res, h, c)
            assert g.n_modes == 0 and all(r.n_reduced > g.n_reduced for r in cb)
        assert _rows(res, coarse, c)[-1].C_err_max > _rows(res, fine, c)[-1].C_err_max
    cb_coarse = _rows(res, coarse, "rbe2")
    assert cb_coarse[-1].freq_err_max <= cb_coarse[0].freq_err_max
    assert all(r.build_seconds >= 0 and r.solve_seconds > 0 for r in res.rows)


def test_verdict_picks_cheapest(study):
    res, _, _ = study
    text = verdict(res.rows, levels=(0.01, 1e-12))
    best = min((r for r in res.rows if r.error <= 0.01), key=lambda r: (r.n_reduced, r.seconds))
    assert f"{best.label} {best.coupling}" in text.splitlines()[0]
    assert text.splitlines()[1].endswith("none")


def test_cli_study_arguments(monkeypatch, tmp_path):
    """``flexarm study`` passes its lists through to :func:`run_study`."""
    import flexarm.studies.arm_study as st
    from flexarm.cli import main

    seen = {}

    def fake(robot, pose, sizes=None, modes=None, couplings=None, out_dir=None, **kw):
        seen.update(pose=pose, sizes=sizes, modes=modes, couplings=couplings, out=out_dir)
        ref = st.Reference(np.ones(2), np.ones(6), 10, 0.03, "rbe2", 1.0)
        return st.StudyResult((), ref, pose, "within 1%: none")

    monkeypatch.setattr(st, "run_study", fake)
    assert main(["study", "--pose", "P2", "--sizes", "0.06,0.03", "--modes", "0,5",
                 "--couplings", "rbe2,k4", "-o", str(tmp_path)]) == 0
    assert seen == {"pose": "P2", "sizes": [0.06, 0.03], "modes": [0, 5],
                    "couplings": ["rbe2", "k4"], "out": str(tmp_path)}


def test_verdict_names_a_seat_model_that_modes_cannot_fix():
    from flexarm.studies.arm_study import StudyRow

    def row(coupling, n, err):
        return StudyRow(0.03, coupling, n, f"CB({n})", 50 + n, 1000, err, err, 0.0, 0.0, 1.0, 0.01)

    rows = [row("rbe2", 0, 0.008), row("rbe2", 5, 0.0003),
            row("rbe3", 0, 0.36), row("rbe3", 5, 0.355)]
    text = verdict(rows, reference_coupling="rbe2").splitlines()
    assert text[0].startswith("within 1%: CB(0) rbe2") and text[1].startswith("within 0.1%: CB(5)")
    assert text[2] == ("rbe3: at best 35.5% from the rbe2 reference, whatever the modes: it models "
                       "the joint seats differently (compare with reference_coupling='rbe3')")
    # within the loosest level somewhere: no such line
    assert len(verdict(rows[:2] + [row("rbe3", 10, 0.009)], reference_coupling="rbe2")
               .splitlines()) == 2


def test_single_mesh_plot_spreads_over_mode_counts(box_robot, tmp_path, monkeypatch):
    """One mesh: every row has the same link FE DOF, so the lower panels plot the error
    against the CB mode count instead of stacking the points at one x; a seat model other
    than the reference's is named so in the legend; the progress lines count down."""
    from pathlib import Path

    import matplotlib.figure

    saved = {}
    real = matplotlib.figure.Figure.savefig

    def savefig(self, fname, *args, **kwargs):
        saved[Path(fname).name] = self
        return real(self, fname, *args, **kwargs)

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", savefig)
    lines = []
    res = run_study(box_robot, "P1", (0.1,), (0, 4), ("rbe2", "rbe3"), tmp_path,
                    progress=lines.append, mesher=sized_box_mesher)
    fig = next(f for f in saved.values() if len(f.axes) == 4)
    low = fig.axes[2]
    for line, rep in zip(low.get_lines(), ("rbe2", "rbe3"), strict=False):
        rows = sorted((r for r in res.rows if r.coupling == rep), key=lambda r: r.n_modes)
        assert list(line.get_xdata()) == [r.n_modes for r in rows] == [0, 4]
        np.testing.assert_allclose(line.get_ydata(),
                                   [max(r.freq_err_max, 1e-9) for r in rows])
    labels = [t.get_text() for t in low.get_legend().get_texts()]
    assert labels == ["rbe2", "rbe3 (seat model differs from reference rbe2)"]
    with open(tmp_path / "arm_study.csv") as fh:  # the CSV holds the plotted errors
        table = [r for r in csv.DictReader(fh) if r["label"] != "full-FE"]
    for line, rep in zip(low.get_lines(), ("rbe2", "rbe3"), strict=False):
        rows = sorted((r for r in table if r["coupling"] == rep), key=lambda r: int(r["n_modes"]))
        np.testing.assert_allclose(line.get_ydata(),
                                   [max(float(r["freq_err_max"]), 1e-9) for r in rows])
    counted = [s for s in lines if s.startswith("[")]
    assert all("ETA" in s for s in counted[:-1]) and "ETA" not in counted[-1]


def test_verdict_estimates_the_discretisation_error(study):
    """Richardson from the two sizes (Tet4: frequencies converge as h^2) with the effective
    edge ratio of the FE DOF counts, on the most-modes rbe2 variant; one size says it
    cannot."""
    from flexarm.studies.arm_study import discretisation_estimate, discretisation_text

    res, out, _ = study
    fine, coarse = (next(r for r in res.rows if r.coupling == "rbe2" and r.n_modes == 12
                         and r.mesh_size == h) for h in (0.05, 0.1))
    f2, f1 = np.array(fine.freq_hz), np.array(coarse.freq_hz)
    ratio = (fine.n_fe_dofs / coarse.n_fe_dofs) ** (1 / 3)
    assert 1.4 < ratio < 2.0  # edges halved, but the thinnest boxes keep their 2 cells
    est = res.discretisation
    assert est.richardson == pytest.approx(np.max(np.abs(f1 - f2) / f2) / (ratio**2 - 1),
                                           rel=1e-12)
    line = res.verdict.splitlines()[-1]
    assert line == est.text() and line in (out / "arm_study_verdict.txt").read_text()
    assert line.startswith(f"discretisation error at 50 mm (Tet4): Richardson from 100 and "
                           f"50 mm (effective edge ratio {ratio:.2f}, CB(12) rbe2) gives about "
                           f"{100 * est.richardson:.2g}%")
    one = [r for r in res.rows if r.mesh_size == 0.05]
    assert discretisation_estimate(one, "rbe2") is None
    assert discretisation_text(None).startswith("discretisation error: not estimated")


@pytest.mark.slow  # a Tet10 full-FE reference at 25 mm: minutes
def test_tet10_gives_a_lower_bound_of_the_mesh_error(study, box_robot):
    """Tet4 against Tet10 on the same grid bounds the Tet4 error from below (nested spaces,
    min-max): checked against a Tet10 model on a twice finer grid, which is closer to
    the exact frequencies than either."""
    import dataclasses

    from flexarm.studies.arm_study import reference_result

    res, _, _ = study
    q = box_robot.pose("P1")
    one = run_study(box_robot, "P1", (0.05,), (12,), ("rbe2",), mesher=sized_box_mesher,
                    tet10=True)
    est = one.discretisation
    assert est.richardson is None and len(est.p_refined) == len(res.reference.freq_hz)
    assert min(est.p_refined) > -1e-9  # Tet4 frequencies above Tet10's on the same mesh
    tet10 = dataclasses.replace(box_robot, options=dataclasses.replace(box_robot.options,
                                                                       element_order=2))
    finer = reference_result(tet10, q, 0.025, mesher=sized_box_mesher)
    true = res.reference.freq_hz / finer.freq_hz - 1
    assert np.all(true >= np.array(est.p_refined) - 1e-6)
    assert est.lower >= 0.8 * true.max()  # ... and a close one: Tet10's own error is small
    assert one.verdict.splitlines()[-1].startswith(
        f"discretisation error at 50 mm (Tet4): at least {100 * est.lower:.2g}% (mode "
        f"{est.worst_mode}; f1 {100 * est.p_refined[0]:.2g}%) against the full FE with Tet10")
    with pytest.raises(ValueError, match="tet10=True needs a Tet4 robot"):
        run_study(tet10, "P1", (0.05,), (12,), ("rbe2",), mesher=sized_box_mesher, tet10=True)
