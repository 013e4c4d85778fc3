"""``flexarm compensate`` from a CSV of poses, its KRL details, its outputs whole or absent
(a full disk: one line, exit 2, nothing left), and ``flexarm history``."""

from __future__ import annotations

import csv
import errno
from importlib.resources import files
from pathlib import Path

import numpy as np
import pytest

from flexarm.robot.formats.krl_read import read_krl
from flexarm.validation.data.formats import write_path
from flexarm.validation.data.measurements import PathData

from ..cli_run import run_cli

THESIS = str(files("flexarm") / "data" / "rapid" / "ldbb_thesis.mod")
QUICK = ["--force", "ballbar:800N", "--proc", "Path_30", "--step", "10", "-q"]


def _tree(folder: Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes()
            for p in sorted(folder.rglob("*")) if p.is_file()}


def _pass_csv(folder: Path) -> Path:
    """Eleven positions of a straight pass, no orientation (the path CSV format)."""
    x = np.linspace(1100.0, 1400.0, 11)
    return write_path(folder / "pass.csv", PathData(
        steps=np.arange(11), points=np.c_[x, np.full(11, -150.0), np.full(11, 500.0)] * 1e-3,
        force=np.full(11, 300.0)))


def test_a_path_csv_becomes_a_krl_pair_with_its_speeds(tmp_path):
    path = _pass_csv(tmp_path)
    out = tmp_path / "milled.src"
    code, text, err = run_cli(["compensate", str(path), "--force", "tool:fx=300", "--step",
                               "10", "--orientation", "0,0,1,0", "--ptp-speed", "30", "-o",
                               str(out), "-q"])
    assert code == 0, err
    assert text.splitlines()[-4:] == [f"wrote {tmp_path / n}" for n in
                                      ("milled.src", "milled.dat", "milled.csv", "milled.png")]
    prog = read_krl(out)
    moves = prog.routines["pass"]
    assert [m.targets for m in moves] == [(f"p{k}",) for k in range(11)]
    assert prog.main_settings["$VEL_AXIS[3]"] == 30.0 and moves[-1].settings["$VEL.CP"] == 0.1
    shifted = np.array([prog.pose(f"p{k}")[0] for k in range(11)])
    x = np.linspace(1100.0, 1400.0, 11)
    shift = shifted - np.c_[x, np.full(11, -150.0), np.full(11, 500.0)]
    assert 0.2 < np.linalg.norm(shift, axis=1).max() < 2.0  # a real shift, ~0.7 mm


@pytest.mark.parametrize("args, message", [
    (["-o", "c.mod", "--ptp-speed", "20"], "--ptp-speed goes with a KRL program"),
    (["-o", "c.mod", "--csv", "c.mod"], "c.mod: named twice among the outputs"),
    (["-o", "c.mod", "--orientation", "0,0,1,0"], "--orientation goes with a CSV of positions"),
    (["-o", "c.src", "--ptp-speed", "0"], "--ptp-speed 0: must be > 0"),
])
def test_option_clashes_are_one_line(tmp_path, args, message):
    args = [str(tmp_path / a) if a.startswith("c.") else a for a in args]
    code, _text, err = run_cli(["compensate", THESIS, *QUICK, *args])
    assert code == 2
    last = err.strip().splitlines()[-1]
    assert last.startswith("flexarm compensate: error: ") and message in last, last
    assert list(tmp_path.iterdir()) == []


def _full_disk_picture(fig, path, *args, **kwargs):
    """A picture writer that leaves half a PNG, then finds the disk full."""
    Path(path).write_bytes(b"\x89PNG half")
    raise OSError(errno.ENOSPC, "No space left on device")


def test_a_full_disk_leaves_nothing_and_says_so_in_one_line(tmp_path, monkeypatch):
    from flexarm.studies.compensation import plots

    monkeypatch.setattr(plots, "save_figure", _full_disk_picture)
    out = tmp_path / "new" / "c.src"
    code, _text, err = run_cli(["compensate", THESIS, *QUICK, "-o", str(out)])
    assert code == 2
    assert err.strip().splitlines() == [f"flexarm compensate: error: {out.with_suffix('.png')}: "
                                        "No space left on device"], err
    assert list(tmp_path.iterdir()) == []  # no program, no .dat, no CSV, no .part folder


def test_a_full_disk_keeps_the_older_complete_output(tmp_path, monkeypatch):
    from flexarm.studies.compensation import plots

    out = tmp_path / "c.mod"
    code, _text, err = run_cli(["compensate", THESIS, *QUICK, "-o", str(out)])
    assert code == 0, err
    (tmp_path / "notes.txt").write_text("the user's own file")
    before = _tree(tmp_path)
    monkeypatch.setattr(plots, "save_figure", _full_disk_picture)
    code, _text, err = run_cli(["compensate", THESIS, *QUICK, "--split", "60", "-o", str(out)])
    assert code == 2 and err.strip().endswith("No space left on device")
    assert _tree(tmp_path) == before and sorted(p.name for p in tmp_path.iterdir()) == \
        ["c.csv", "c.mod", "c.png", "notes.txt"]


# --- history ---------------------------------------------------------------------------
def _circles(folder: Path) -> list[Path]:
    """Path_30's circle read with a radial error of 1.2, 0.3 and 0.01 mm (cos 2θ)."""
    from flexarm.robot.formats.rapid import read_rapid
    from flexarm.robot.paths import fit_circle, sample_procedure

    p = sample_procedure(read_rapid(THESIS).procedure("Path_30"), step_mm=1).points_m
    c, n, r = fit_circle(p)
    u = np.cross(n, [1.0, 0.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(n, u)
    t = np.linspace(0.0, 2 * np.pi, 400, endpoint=False)
    out = []
    for k, b in enumerate((1.2e-3, 0.3e-3, 0.01e-3)):
        rad = r + b * np.cos(2 * t)
        pts = c + rad[:, None] * (np.outer(np.cos(t), u) + np.outer(np.sin(t), v))
        out.append(write_path(folder / f"step{k}.csv", PathData(
            steps=np.arange(len(t)), points=pts, force=np.full(len(t), 800.0))))
    return out


def test_history_writes_the_picture_and_the_figures(tmp_path):
    steps = _circles(tmp_path)
    out = tmp_path / "history.png"
    labels = ["nominal program", "compensated, nominal model", "compensated, identified"]
    code, text, err = run_cli(["history", *map(str, steps), "--program", THESIS,
                               *[a for x in labels for a in ("--label", x)], "-o", str(out),
                               "-q"])
    assert code == 0, err
    assert text.splitlines()[-2:] == [f"wrote {out}", f"wrote {out.with_suffix('.csv')}"]
    lines = out.with_suffix(".csv").read_text().splitlines()
    rows = list(csv.reader(x for x in lines if not x.startswith("#")))[1:]
    assert [r[0] for r in rows] == labels and {r[1] for r in rows} == {"Path_30"}
    # cos 2θ sampled evenly: RMS b / sqrt(2), peak b (the files hold mm to 1e-9)
    for r, b in zip(rows, (1.2, 0.3, 0.01), strict=True):
        assert abs(float(r[5]) - b / np.sqrt(2)) < 1e-8 and abs(float(r[6]) - b) < 1e-8
    assert float(rows[2][8]) == pytest.approx(120.0, rel=1e-6)
    assert "compensated, identified        Path_30" in text


@pytest.mark.parametrize("args, message", [
    (["-o", "h.txt"], "-o h.txt: the picture ends in .png, .svg, .pdf"),
    (["-o", "h.png", "--label", "one"], "--label: 1 labels for 3 measured paths"),
    (["-o", "h.png", "--csv", "h.png"], "h.png: named twice among the files to write"),
])
def test_history_errors_are_one_line(tmp_path, args, message):
    steps = _circles(tmp_path)
    before = sorted(tmp_path.iterdir())
    args = [str(tmp_path / a) if a.startswith("h.") else a for a in args]
    code, _text, err = run_cli(["history", *map(str, steps), "--program", THESIS, *args])
    assert code == 2
    last = err.strip().splitlines()[-1]
    assert last.startswith("flexarm history: error: ") and message in last, last
    assert sorted(tmp_path.iterdir()) == before
