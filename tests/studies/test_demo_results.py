"""The demo's results are frozen, survive the trip from a worker process, and its
tables go through one writer."""

from __future__ import annotations

import dataclasses
import pickle

import pytest

from flexarm.studies.demo_results import DemoResult, StepResult, write_table


def test_step_result_is_frozen_and_pickles():
    figures = {"f1_Hz": 7.5}
    step = StepResult(["## A", ""], figures)
    figures["f1_Hz"] = 0.0  # the result keeps its own copy
    assert step.lines == ("## A", "") and step.figures["f1_Hz"] == 7.5
    with pytest.raises(dataclasses.FrozenInstanceError):
        step.lines = ()
    with pytest.raises(TypeError):
        step.figures["f1_Hz"] = 1.0
    back = pickle.loads(pickle.dumps(step))
    assert back.lines == step.lines and dict(back.figures) == dict(step.figures)


def test_demo_result_joins_steps_in_order_and_writes_the_index_text(tmp_path):
    run = DemoResult.of(tmp_path, [StepResult(["## One", "a"], {"b_mm": 2.0, "a_mm": 1.0}),
                                   StepResult(["## Two"], {"c_kg": 3.0})], 12.34)
    assert run.folder == tmp_path and run.lines == ("## One", "a", "## Two")
    assert list(run.figures) == ["b_mm", "a_mm", "c_kg"]
    assert run.index_text() == "# flexarm demo\n\nRun time 12.3 s.\n\n## One\na\n## Two\n"
    with pytest.raises(TypeError):
        run.figures["c_kg"] = 0.0
    assert dict(pickle.loads(pickle.dumps(run)).figures) == dict(run.figures)


def test_write_table_formats_floats_and_leaves_no_partial_file(tmp_path):
    import numpy as np

    path = write_table(tmp_path / "t.csv", ["link", "tets", "f1_Hz", "share"],
                       [["base", 7129, 1965.9051523456, np.float64(0.25)]])
    assert path.read_text() == "link,tets,f1_Hz,share\nbase,7129,1965.905152,0.25\n"
    assert [p.name for p in tmp_path.iterdir()] == ["t.csv"]
