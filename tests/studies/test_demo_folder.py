"""Multi-file outputs appear complete or not at all: demo and study folders."""

from __future__ import annotations

import os

import pytest

from flexarm.fe import files
from flexarm.fe.files import atomic_folder
from flexarm.studies import demo
from flexarm.studies.demo_results import StepResult


def _tree(folder):
    return {str(p.relative_to(folder)): p.read_text() for p in sorted(folder.rglob("*"))
            if p.is_file()}


def test_complete_output_replaces_same_names_keeps_others_index_last(tmp_path, monkeypatch):
    out = tmp_path / "run"
    (out / "maps").mkdir(parents=True)
    (out / "maps" / "old.png").write_text("old map")
    (out / "table.csv").write_text("old")
    (out / "notes.txt").write_text("the user's own file")
    order = []
    real = os.replace

    def replace(src, dst):
        order.append(os.path.basename(dst))
        return real(src, dst)

    monkeypatch.setattr(files.os, "replace", replace)
    with atomic_folder(out, last="index.md") as tmp:
        (tmp / "maps").mkdir()
        (tmp / "maps" / "new.png").write_text("new map")
        (tmp / "table.csv").write_text("new")
        (tmp / "index.md").write_text("done")
        (tmp / "zzz.csv").write_text("z")
    assert _tree(out) == {"index.md": "done", "maps/new.png": "new map",
                          "notes.txt": "the user's own file", "table.csv": "new",
                          "zzz.csv": "z"}
    assert order[-1] == "index.md"  # its presence means the rest is there
    assert [p.name for p in tmp_path.iterdir()] == ["run"]  # nothing left aside


@pytest.mark.parametrize("exc", [KeyboardInterrupt, RuntimeError])
def test_interrupted_output_leaves_the_folder_as_it_was(tmp_path, exc):
    out = tmp_path / "run"
    out.mkdir()
    (out / "table.csv").write_text("complete old run")
    with pytest.raises(exc), atomic_folder(out, last="index.md") as tmp:
        (tmp / "table.csv").write_text("half")
        raise exc
    assert _tree(out) == {"table.csv": "complete old run"}
    assert [p.name for p in tmp_path.iterdir()] == ["run"]


def test_folder_of_a_killed_run_is_swept(tmp_path):
    out = tmp_path / "run"
    dead = tmp_path / ".run.part-999999999-abc"  # no such process
    live = tmp_path / f".run.part-{os.getpid()}-xyz"  # another run of this process
    for d in (dead, live):
        d.mkdir()
        (d / "half.csv").write_text("x")
    with atomic_folder(out) as tmp:
        (tmp / "a.csv").write_text("a")
    assert not dead.exists() and live.exists()
    with pytest.raises(NotADirectoryError):
        with atomic_folder(out / "a.csv"):
            pass


def _fake_steps(monkeypatch, fail_at: str | None):
    def step(name):
        def run(out, progress, *args):
            (out / f"{name}.csv").write_text(name)
            if name == fail_at:
                raise KeyboardInterrupt
            return StepResult([f"## {name}"], {f"{name}_Hz": 1.0})
        return run

    monkeypatch.setattr(demo, "emodel_step", step("emodel"))
    monkeypatch.setattr(demo, "flexible_step", step("flexible"))
    monkeypatch.setattr(demo, "measurement_step", step("measurements"))


def test_demo_interrupted_leaves_no_half_folder(tmp_path, monkeypatch):
    _fake_steps(monkeypatch, fail_at="flexible")
    with pytest.raises(KeyboardInterrupt):
        demo.run_demo(tmp_path / "flexarm-demo", jobs=1)
    assert list(tmp_path.iterdir()) == []
    _fake_steps(monkeypatch, fail_at=None)
    result = demo.run_demo(tmp_path / "flexarm-demo", jobs=1)
    assert result.folder == tmp_path / "flexarm-demo"
    assert sorted(_tree(result.folder)) == ["emodel.csv", "flexible.csv", "index.md",
                                            "measurements.csv"]
    assert "## flexible" in (result.folder / "index.md").read_text()
    assert [p.name for p in tmp_path.iterdir()] == ["flexarm-demo"]


def test_study_files_are_written_together_or_not_at_all(tmp_path, monkeypatch):
    from flexarm.studies import arm_study

    def half(result, out):
        (out / "arm_study.csv").write_text("half")
        raise KeyboardInterrupt

    monkeypatch.setattr(arm_study, "_write_study", half)
    with pytest.raises(KeyboardInterrupt):
        arm_study.write_study(None, tmp_path / "study")
    assert list(tmp_path.iterdir()) == []

    def whole(result, out):
        return tuple((out / n).write_text(n) and out / n for n in ("arm_study.csv", "v.txt"))

    monkeypatch.setattr(arm_study, "_write_study", whole)
    files = arm_study.write_study(None, tmp_path / "study")
    assert files == (tmp_path / "study" / "arm_study.csv", tmp_path / "study" / "v.txt")
    assert all(f.read_text() == f.name for f in files)
