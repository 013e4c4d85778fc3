"""The diagnosis report: unidentifiable directions named in words, 120 columns, every
column defined, joints counted from 1."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.validation.diagnosis.identifiability import weak_directions
from flexarm.validation.diagnosis.text import COLUMNS, WIDTH

NAMES = [f"joint {j} torsion" for j in range(1, 5)]


def test_null_direction_names_the_parameters_it_involves():
    rng = np.random.default_rng(1)
    base = rng.normal(size=(40, 2))
    # joint 3 = joint 1 - 2 joint 2 exactly; joint 4 moves nothing
    X = np.column_stack([base[:, 0], base[:, 1], base[:, 0] - 2 * base[:, 1], np.zeros(40)])
    weak = weak_directions(X, NAMES)
    assert weak[0] == "joint 4 torsion moves the TCP in no measured direction: unidentifiable"
    # the first three columns are linearly dependent: all three are named
    assert weak[1] == ("joint 1 torsion and joint 2 torsion and joint 3 torsion move the TCP "
                       "alike: only their combination is identifiable")
    assert len(weak) == 2


def test_nearly_parallel_columns_are_named_with_their_correlation():
    rng = np.random.default_rng(2)
    a, b, c, d = rng.normal(size=(4, 50))
    X = np.column_stack([a, a + 0.1 * c, b, d])
    cos = X[:, 0] @ X[:, 1] / np.linalg.norm(X[:, 0]) / np.linalg.norm(X[:, 1])
    assert weak_directions(X, NAMES) == (
        f"joint 1 torsion and joint 2 torsion move the TCP alike (correlation {cos:.2f})",)
    assert weak_directions(X, NAMES, corr=0.999) == ()


def test_shipped_lab_report_fits_120_columns_and_defines_its_columns():
    from importlib.resources import files

    from flexarm.validation.workflow import run_diagnosis

    run = run_diagnosis(str(files("flexarm") / "data" / "lab" / "lab_hidden_effect.csv"))
    text = run.text()
    assert max(map(len, text.splitlines())) <= WIDTH
    # the demo arm's joint 6 turns the TCP about its own axis: its torsion is invisible
    assert ("  joint 6 torsion moves the TCP in no measured direction: unidentifiable"
            in text.splitlines())
    assert "joint_" not in text
    flat = " ".join(text.split())
    assert " ".join(("columns: " + COLUMNS).split()) in flat
    for column in ("dBIC:", "unique:", "norm:", "[n]:"):
        assert column in COLUMNS
    # every [n] in a table has its detail line
    refs = {int(m) for m in __import__("re").findall(r"\[(\d+)\]\s*$", text, flags=8)}
    assert refs and all(f"  [{k}] " in text for k in refs)


def test_truth_files_count_joints_from_1():
    import json
    from importlib.resources import files

    truth = json.loads((files("flexarm") / "data" / "lab" / "truth" /
                        "lab_hidden_effect.truth.json").read_text())
    joints = [e["joint_number"] for e in truth["effects"]]
    assert min(j for j in joints if j is not None) == 1
    backlash = [e for e in truth["effects"] if e["kind"] == "backlash"]
    assert [e["joint_number"] for e in backlash] == [2]  # the README's "joint-2 backlash"
    assert backlash[0]["params"]["width"] == pytest.approx(1e-4)


def test_diagnosis_table_and_repr_for_notebooks():
    from importlib.resources import files

    from flexarm.validation.workflow import run_diagnosis

    dg = run_diagnosis(str(files("flexarm") / "data" / "lab" / "lab_hidden_effect.csv")).diagnosis
    frame = dg.to_dataframe()
    assert len(frame) == sum(len(s.candidates) for s in dg.steps)
    first = dg.steps[0].candidates[0]
    row = frame.iloc[0]
    assert (row["version"], row["candidate"], row["status"]) == (0, first.label, first.status)
    assert row["dBIC"] == first.dbic and row["unique"] == first.unique
    assert frame[frame.status == "accepted"].candidate.tolist() == ["joint 2 backlash"]
    text = repr(dg)
    assert len(text) < 300 and "accepted: joint 2 backlash" in text
    assert f"chi2_red {dg.final.chi2_red:.3f}" in text
