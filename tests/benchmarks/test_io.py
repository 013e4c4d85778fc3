"""``benchmarks/io.py``: the generated file is a valid static measurement file holding
the numbers it was generated from, and a step reports what it read."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np

_PATH = Path(__file__).parents[2] / "benchmarks" / "io.py"


def _bench():
    spec = importlib.util.spec_from_file_location("flexarm_bench_io", _PATH)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_generated_file_reads_back_exactly(tmp_path):
    from flexarm.validation import read_measurements

    bench = _bench()
    path = tmp_path / "static.csv"
    assert bench.write_static_csv(path, 2_000, seed=3) > 0.1
    data = read_measurements(path)
    # the same draws, rounded as written, in metres
    d = np.random.default_rng(3).normal(size=(2_000, 3)) * 0.05
    d[::10] = 0.0
    np.testing.assert_array_equal(data.disp, np.array([[float(f"{v:.4f}e-3") for v in r]
                                                       for r in d]))
    assert len(set(data.series)) == 200
    np.testing.assert_array_equal(data.force[:, 1], 200.0 * (np.arange(2_000) % 10))


def test_step_reports_rows_time_and_memory(tmp_path):
    bench = _bench()
    path = tmp_path / "static.csv"
    bench.write_static_csv(path, 500)
    line = bench.run_step("read", path, timeout=120)
    assert line.split(":")[0].strip() == "read" and "500 rows in" in line
    assert "MB above the imports" in line
    assert "failed" in bench.run_step("read", tmp_path / "absent.csv", timeout=120)
