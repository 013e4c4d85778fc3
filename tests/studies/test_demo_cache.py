"""The demo's own results kept between runs (:mod:`flexarm.studies.demo_cache`), and the
two-process run that reads them."""

from __future__ import annotations

import os
import pickle
import threading
from types import SimpleNamespace

import numpy as np
import pytest

from flexarm.studies import demo
from flexarm.studies.demo_cache import demo_result
from flexarm.studies.demo_results import StepResult


@pytest.fixture
def own_cache(tmp_path, monkeypatch):
    """An empty cache of this test's own."""
    monkeypatch.setenv("FLEXARM_CACHE", str(tmp_path / "cache"))
    return tmp_path / "cache"


def test_computed_once_then_read_back_equal(own_cache):
    calls = []

    def compute():
        calls.append(1)
        return {"stiffness": np.linspace(1e6, 2e6, 7), "label": "E-model"}

    first = demo_result("map", compute, "P1", 60)
    second = demo_result("map", compute, "P1", 60)
    assert len(calls) == 1
    np.testing.assert_array_equal(first["stiffness"], np.linspace(1e6, 2e6, 7))
    np.testing.assert_array_equal(second["stiffness"], first["stiffness"])
    assert second["label"] == "E-model" and len(list((own_cache / "demo").glob("*.pkl"))) == 1


def test_key_covers_name_inputs_and_package(own_cache, monkeypatch):
    from flexarm.studies import demo_cache

    calls = []

    def compute():
        calls.append(1)
        return len(calls)

    assert demo_result("map", compute, "P1", 60) == 1
    assert demo_result("map", compute, "P1", 30) == 2  # another grid
    assert demo_result("study", compute, "P1", 60) == 3  # another result
    with monkeypatch.context() as edited:
        edited.setattr(demo_cache, "package_digest", lambda: "0" * 64)  # edited code
        assert demo_result("map", compute, "P1", 60) == 4
    assert demo_result("map", compute, "P1", 60) == 1 and len(calls) == 4


def test_the_computing_run_draws_what_later_runs_read(own_cache):
    """A picture's cache key pickles what it draws.  An array read back from a pickle
    has its own dtype object, which a pickle writes out again where NumPy's shared one
    is referred back to, so the key of a picture drawn from a freshly computed array
    differs from the key of the same picture drawn from the stored one: the first warm
    run would draw every such picture again.  The computing run gets the stored value."""
    fresh = np.arange(5.0)
    first = demo_result("values", lambda: {"a": np.arange(5.0)}, "dtype")
    second = demo_result("values", lambda: {"a": np.arange(5.0)}, "dtype")
    drawn = [pickle.dumps((r["a"], np.zeros(2))) for r in (first, second)]
    assert drawn[0] == drawn[1]
    assert pickle.dumps((fresh, np.zeros(2))) != drawn[1]  # what the first run had drawn


def test_unwritable_cache_still_gives_the_value(tmp_path, monkeypatch):
    blocked = tmp_path / "file"
    blocked.write_text("not a folder")
    monkeypatch.setenv("FLEXARM_CACHE", str(blocked / "cache"))
    assert demo_result("map", lambda: [1.5, 2.5], "P1") == [1.5, 2.5]


def test_worker_is_forked_only_from_one_thread_on_pthreads_blas(monkeypatch):
    import sys

    import threadpoolctl

    loaded = []
    monkeypatch.setattr(demo, "_load_shared", lambda: loaded.append(1))
    monkeypatch.setattr(sys, "platform", "linux")
    monkeypatch.setattr(threading, "active_count", lambda: 1)
    pools = [{"internal_api": "openblas", "threading_layer": "pthreads"}]
    monkeypatch.setattr(threadpoolctl, "threadpool_info", lambda: pools)
    assert demo._ready_to_fork() and len(loaded) == 1
    pools.append({"internal_api": "openmp", "threading_layer": None})  # libgomp loaded
    assert not demo._ready_to_fork()
    pools.pop()
    monkeypatch.setattr(threading, "active_count", lambda: 2)  # another thread runs
    assert not demo._ready_to_fork()
    monkeypatch.setattr(threading, "active_count", lambda: 1)
    monkeypatch.setattr(sys, "platform", "darwin")
    assert not demo._ready_to_fork() and len(loaded) == 2  # nothing loaded for a spawn


def test_two_process_run_forks_the_worker_and_keeps_the_index_order(tmp_path, monkeypatch):
    """jobs=2: the worker (forked, so it sees these stand-ins) computes the study's
    references, then runs the E-model step, and sends its progress lines back; the study
    is made here only once the references are done; the index is in step order, as in
    one process."""
    from flexarm.studies.demo_models import FlexibleArmPart

    monkeypatch.setattr(demo, "_load_shared", lambda: None)
    monkeypatch.setattr(demo, "is_warm", lambda *inputs: False)
    monkeypatch.setattr(demo, "mark_warm", lambda *inputs: None)
    if not demo._ready_to_fork():
        pytest.skip("the worker is spawned here: it would run the real steps")
    done = tmp_path / "references.pid"

    def step(name):
        def run(out, progress):
            progress(f"{name}: running")
            return StepResult([f"## {name}"], {f"{name}_pid": float(os.getpid())})
        return run

    def references(out, progress):
        progress("references: running")
        done.write_text(str(os.getpid()))

    def flexible_arm(out, progress):
        progress("flexible: running")
        return FlexibleArmPart(("## flexible",), ("flexible tail",),
                               (("flexible_pid", float(os.getpid())),), 0.5)

    def study(out, progress):
        # a stand-in for the StudyResult: what with_study reads of it
        return SimpleNamespace(pose="P1", verdict="v", discretisation=None,
                               reference=SimpleNamespace(n_dofs=int(done.read_text())))

    monkeypatch.setitem(demo._WORKER_JOBS, "references", references)
    monkeypatch.setitem(demo._WORKER_JOBS, "emodel", step("emodel"))
    monkeypatch.setattr(demo, "flexible_arm_step", flexible_arm)
    monkeypatch.setattr(demo, "measurement_step", step("measurement"))
    monkeypatch.setattr(demo, "study_variants", lambda progress: progress("variants: running"))
    monkeypatch.setattr(demo, "accuracy_study", study)
    said = []
    result = demo.run_demo(tmp_path / "out", progress=said.append, jobs=2)
    lines = result.lines
    assert lines[0] == "## emodel" and lines[1] == "## flexible" and lines[-1] == "## measurement"
    assert lines[-2] == "flexible tail" and lines[2].startswith("- Accuracy study at P1")
    worker = int(done.read_text())
    assert f"({worker} DOF)" in lines[2] and worker != os.getpid()
    figures = dict(result.figures)
    assert figures["flexible_pid"] == figures["measurement_pid"] == os.getpid()
    assert figures["emodel_pid"] == worker
    assert figures["flexible_map_y_weakest_share"] == 0.5
    assert {"emodel: running", "flexible: running", "measurement: running",
            "references: running", "variants: running"} <= set(said)
    assert (tmp_path / "out" / "index.md").read_text() == result.index_text()


def test_a_warm_run_stays_in_one_process(tmp_path, monkeypatch):
    """After a complete run with the same options every step is mostly cache reads:
    jobs=2 then runs them here, in index order (and notes the run complete again)."""
    monkeypatch.setattr(demo, "is_warm", lambda size, part: (size, part) == (0.03, False))
    marked = []
    monkeypatch.setattr(demo, "mark_warm", lambda *inputs: marked.append(inputs))

    def step(name):
        def run(out, progress):
            return StepResult([f"## {name}"], {f"{name}_pid": float(os.getpid())})
        return run

    monkeypatch.setitem(demo._WORKER_JOBS, "emodel", step("emodel"))
    monkeypatch.setattr(demo, "emodel_step", step("emodel"))
    monkeypatch.setattr(demo, "measurement_step", step("measurement"))
    monkeypatch.setattr(demo, "flexible_step", step("flexible"))
    result = demo.run_demo(tmp_path / "out", jobs=2)
    assert result.lines == ("## emodel", "## flexible", "## measurement")
    assert set(dict(result.figures).values()) == {float(os.getpid())}
    assert marked == [(0.03, False)]
