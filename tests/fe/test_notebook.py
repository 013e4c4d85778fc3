"""Notebook helpers (flexarm/fe/notebook.py): figure ranges, name lists, pandas on demand."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from flexarm.fe import MissingDependencyError, TetMesh
from flexarm.fe.eigen import Modes
from flexarm.fe.notebook import data_frame, names, span


def test_span_states_min_and_max_in_any_order():
    rng = np.random.default_rng(3)
    for _ in range(20):
        v = rng.uniform(1, 1000, rng.integers(2, 30))
        lo, hi = span(v, "Hz").removesuffix(" Hz").split("–")
        assert float(lo) == pytest.approx(v.min(), rel=1e-3)
        assert float(hi) == pytest.approx(v.max(), rel=1e-3)
    assert span([5.0], "N") == "5 N" and span(np.zeros(0)) == "none"


def test_names_cut_long_lists_and_labels():
    assert names(["a", "b"]) == "a, b"
    assert names(list("abcdefg"), limit=3) == "a, b, c, … (+4)"
    assert names(["x" * 40]) == "x" * 23 + "…"


def test_data_frame_keeps_column_order_and_values():
    f = data_frame({"b": [1.5, 2.5], "a": ["p", "q"]})
    assert f.columns.tolist() == ["b", "a"] and f["b"].tolist() == [1.5, 2.5]


def test_missing_pandas_is_named(monkeypatch):
    modes = Modes(np.array([1.0, 4.0]), np.eye(3, 2), scale=1.0)
    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas -> ImportError
    with pytest.raises(MissingDependencyError, match="'pandas'") as err:
        modes.to_dataframe()
    assert err.value.package == "pandas"
    assert repr(TetMesh.unit_tet()).startswith("TetMesh(Tet4")  # reprs need no pandas
