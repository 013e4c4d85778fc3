"""Modes of flexarm/fe/eigen.py in a notebook: a short repr and a table of the modes."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.fe import MATERIALS, TetMesh, assemble, modes


@pytest.fixture(scope="module")
def free_box():
    K, M = assemble(TetMesh.box((1.0, 0.1, 0.05), (10, 2, 1)), MATERIALS["steel"])
    return modes(K, M, n=12)


def test_repr_states_count_rigid_modes_and_elastic_range(free_box):
    m = free_box
    text = repr(m)
    assert len(text) < 300 and "\n" not in text
    assert text.startswith("Modes(12 modes, 6 rigid, elastic ")
    lo, hi = text.split("elastic ")[1].split(" Hz")[0].split("–")
    assert float(lo) == pytest.approx(m.freq_hz[6], rel=1e-3)
    assert float(hi) == pytest.approx(m.freq_hz[-1], rel=1e-3)
    assert text.endswith(f"shapes {m.vectors.shape[0]} DOF)")


def test_dataframe_holds_every_mode(free_box):
    m = free_box
    f = m.to_dataframe()
    assert f.columns.tolist() == ["mode", "f_Hz", "omega2_rad2_per_s2", "rigid"]
    assert f["mode"].tolist() == list(range(1, 13))
    assert np.array_equal(f["f_Hz"].to_numpy(), m.freq_hz)
    assert np.allclose((2 * np.pi * f["f_Hz"]) ** 2, np.clip(f["omega2_rad2_per_s2"], 0, None))
    assert f["rigid"].tolist() == [True] * 6 + [False] * 6
