"""The demo's steps produce their files and the figures the README quotes."""

from __future__ import annotations

import pytest

from flexarm.studies.demo import _init_worker, _worker_job, run_demo
from flexarm.studies.demo_measurements import measurement_step


def test_measurement_demo_error_falls_into_band(tmp_path):
    said = []
    step = measurement_step(tmp_path, said.append)
    lines, f = step.lines, step.figures
    assert any(s.startswith("measurements:") for s in said)
    # nominal stiffnesses are 30 % off: far outside the noise band ...
    assert f["measurements_chi2_red_nominal"] > 10
    # ... the fitted baseline still misses the hidden backlash, the final model does not
    assert f["measurements_chi2_red_final"] < f["measurements_chi2_red_fitted_baseline"]
    assert 0.8 < f["measurements_chi2_red_final"] < 1.2
    assert f["measurements_rms_final_um"] < 1.6 * 15.0
    text = "\n".join(lines)
    assert "joint 2 backlash" in text
    for name in ("robot_v1.toml", "diagnosis/history.png", "measurements_v1/errors.csv"):
        assert (tmp_path / name).stat().st_size > 0


@pytest.mark.slow
def test_full_demo_writes_index(tmp_path):
    result = run_demo(tmp_path / "demo")
    index = (tmp_path / "demo" / "index.md").read_text()
    assert "E-model" in index and "backlash" in index
    assert 5.0 < result.figures["emodel_P1_defl_800N_y_mm"] < 7.0
    assert index == result.index_text()


def test_emodel_step_in_a_spawned_worker_sends_result_and_progress_back(tmp_path):
    # the way run_demo runs it where it cannot fork: the step's result is pickled back
    # and its progress lines come through the queue
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    ctx = multiprocessing.get_context("spawn")
    queue = ctx.SimpleQueue()
    with ProcessPoolExecutor(1, mp_context=ctx, initializer=_init_worker,
                             initargs=(queue,)) as pool:
        step = pool.submit(_worker_job, str(tmp_path), "emodel").result()
    said = []
    while not queue.empty():
        said.append(queue.get())
    assert said and all(s.startswith("arm: ") for s in said)
    assert 5.0 < step.figures["emodel_P1_defl_800N_y_mm"] < 7.0
    assert (tmp_path / "emodel_poses.csv").stat().st_size > 0


def test_can_spawn_falls_back_without_semaphores(monkeypatch):
    import multiprocessing

    from flexarm.studies.demo import _can_spawn

    assert _can_spawn()

    class NoLocks:
        def SimpleQueue(self):  # noqa: N802 - the multiprocessing name
            raise OSError(38, "Function not implemented")

    monkeypatch.setattr(multiprocessing, "get_context", lambda method: NoLocks())
    assert not _can_spawn()


def test_in_order_run_joins_the_steps_in_index_order(tmp_path, monkeypatch):
    # without semaphores jobs=2 falls back to one process: every step in index order
    from flexarm.studies import demo
    from flexarm.studies.demo_results import StepResult

    def fake(name):
        return lambda out, progress, *size: StepResult([f"## {name}"], {f"{name}_Hz": 1.0})

    for name in ("part", "emodel", "flexible", "measurement"):
        monkeypatch.setattr(demo, f"{name}_step", fake(name))
    monkeypatch.setattr(demo, "_can_spawn", lambda: False)
    said = []
    result = demo.run_demo(tmp_path, progress=said.append, part=True, jobs=2)
    assert said[0].startswith("demo: no process semaphores")
    assert result.lines == ("## part", "## emodel", "## flexible", "## measurement")
    assert list(result.figures) == ["part_Hz", "emodel_Hz", "flexible_Hz", "measurement_Hz"]
    assert (tmp_path / "index.md").read_text() == result.index_text()


#: Files that carry wall times (the accuracy study reports how long each variant took).
_TIMED = ("index.md", "study/")


@pytest.mark.slow
def test_warm_demo_serves_identical_pictures_from_the_cache(tmp_path):
    from flexarm.fe.cache import cache_root

    run_demo(tmp_path / "a")
    pictures = cache_root() / "pictures"
    before = set(pictures.glob("*.bin"))
    run_demo(tmp_path / "b")
    new = set(pictures.glob("*.bin")) - before
    files = sorted(p.relative_to(tmp_path / "a") for p in (tmp_path / "a").rglob("*")
                   if p.is_file())
    kept = [f for f in files if not str(f).startswith(_TIMED)]
    assert sum(f.suffix in (".png", ".gif") for f in kept) >= 15
    for f in kept:
        assert (tmp_path / "a" / f).read_bytes() == (tmp_path / "b" / f).read_bytes(), f
    # only the pictures of timed results were drawn again
    timed = [f for f in files if str(f).startswith("study/") and f.suffix == ".png"]
    assert len(new) <= len(timed)
