"""Scale and interrupts through ``flexarm.cli.main``: a multi-file output appears whole or
not at all (Ctrl-C, a full disk), a deeply nested RAPID module is one clear line, an
exported ``.mat`` is the same bytes on every run, and big measurement files are read
in bulk and summarised.  Times and memory at scale are ``benchmarks/io.py``'s, not a
test's.
"""

from __future__ import annotations

import dataclasses
import errno
import gc
from pathlib import Path

import numpy as np
import pytest

from flexarm.cli import main
from flexarm.validation import example_path

from .test_hostile import _last_error, static_csv

STATIC = example_path("static")


@pytest.fixture(autouse=True)
def _caches(monkeypatch, tmp_path):
    import os

    # the session's cache (conftest), never a folder inside the case's own output folder
    monkeypatch.setenv("FLEXARM_CACHE", os.environ.get("FLEXARM_TEST_CACHE")
                       or os.environ["FLEXARM_CACHE"])


def _tree(folder: Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes()
            for p in sorted(folder.rglob("*")) if p.is_file()}


def _full_disk(*args, **kwargs):
    raise OSError(errno.ENOSPC, "No space left on device")  # what write() raises


def _interrupt(*args, **kwargs):
    raise KeyboardInterrupt  # what Ctrl-C raises in the main thread


def _half_then(exc):
    """A picture writer that leaves half a PNG, then fails with ``exc``."""
    def write(path, *args, **kwargs):
        Path(path).write_bytes(b"\x89PNG half")
        raise exc
    return write


# --- compare -o: whole or nothing ------------------------------------------------------
@pytest.mark.parametrize("fault, code, last", [
    (_half_then(KeyboardInterrupt), 130, "flexarm compare: interrupted"),
    (_half_then(OSError(errno.ENOSPC, "No space left on device")), 2,
     "flexarm compare: error: {out}: No space left on device"),
], ids=["ctrl-c", "full-disk"])
def test_compare_report_is_whole_or_absent(tmp_path, capsys, monkeypatch, fault, code, last):
    from flexarm.validation.static import report

    monkeypatch.setattr(report, "plot_deflection", fault)  # errors.csv is written by then
    out = tmp_path / "new" / "report"
    assert main(["compare", str(STATIC), "-o", str(out)]) == code
    assert capsys.readouterr().err.splitlines()[-1] == last.format(out=out)
    assert list(tmp_path.iterdir()) == []  # no report, no parent made for it, no .part


def test_compare_report_keeps_the_older_complete_one(tmp_path, capsys, monkeypatch):
    from flexarm.validation.static import report

    out = tmp_path / "report"
    assert main(["compare", str(STATIC), "-o", str(out)]) == 0
    (out / "notes.txt").write_text("the user's own file")
    before = _tree(out)
    # the disk fills up half way: errors.csv and a picture are written by then
    monkeypatch.setattr(report, "write_residuals", _half_then(OSError(errno.ENOSPC, "No "
                                                                      "space left on device")))
    assert main(["compare", str(STATIC), "-o", str(out)]) == 2
    line = _last_error(capsys.readouterr().err, "compare")
    assert line.endswith(f"{out}: No space left on device"), line
    assert _tree(out) == before and sorted(p.name for p in tmp_path.iterdir()) == ["report"]


def test_diagnosis_history_is_whole_or_absent(tmp_path, monkeypatch):
    from flexarm.validation.diagnosis import history

    monkeypatch.setattr(history, "plot_history", _half_then(KeyboardInterrupt))

    class Step:
        label, chi2_red, band, rms_fit, rms_heldout, freq_rms, n_unpaired = (
            "E-model", 1.0, (0.9, 1.1), 1e-5, 2e-5, float("nan"), 0)

    diagnosis = type("D", (), {"steps": [Step()], "accepted": []})()
    with pytest.raises(KeyboardInterrupt):
        history.write_history(tmp_path / "hist", diagnosis)
    assert list(tmp_path.iterdir()) == []


# --- export-exudyn and lab: every file or none ----------------------------------------
#: A Craig-Bampton arm on the demo's pinned tetrahedra: a script, its assembly and one
#: Exudyn file per link.
EXUDYN = ["export-exudyn", "--model", "cb", "--mesh-size", "0.045", "--modes", "4",
          "--pose", "P1", "--no-check", "-q"]
#: A lab run with a universal file and its points table beside the static CSV.
LAB = ["lab", "--poses", "P1", "--loads", "0:200:100", "--dirs", "z", "--n-modes", "2", "-q"]


def _exudyn(monkeypatch, fault: str) -> str:
    """Ctrl-C when the script is written last (the assembly and every link file written
    by then), or the disk full in the first archive (a link file); returns the file the
    error names."""
    pytest.importorskip("exudyn", reason="Exudyn (pip install flexarm[mbs])")
    from flexarm.studies.exudyn import standalone

    if fault == "ctrl-c":
        monkeypatch.setattr(standalone, "standalone_script", _interrupt)
    else:
        monkeypatch.setattr("numpy.lib.format.write_array", _full_disk)
    return "arm_0_base.npz"


def _lab(monkeypatch, fault: str) -> str:
    """Ctrl-C in the static CSV, written last (the universal file and its points table
    written by then), or the disk full in the points table, after the universal file."""
    from flexarm.validation.lab import virtual_lab

    if fault == "ctrl-c":
        monkeypatch.setattr(virtual_lab, "write_static", _half_then(KeyboardInterrupt))
    else:
        monkeypatch.setattr("flexarm.validation.data.formats._table.csv.writer", _full_disk)
    return "lab.points.csv"


def _argv(command: str, folder: Path, other: bool = False) -> list[str]:
    """The command writing into ``folder``; ``other``: other contents (another pose or
    seed), so that a file written again is not the same bytes."""
    if command == "export-exudyn":
        return [*EXUDYN, *(["--pose", "P2"] if other else []), "-o", str(folder / "arm.py")]
    return [*LAB, *(["--seed", "7"] if other else []), "--modal", str(folder / "lab.uff"),
            "-o", str(folder / "lab.csv")]


FAULTS = {"export-exudyn": _exudyn, "lab": _lab}


@pytest.mark.parametrize("fault", ["ctrl-c", "full-disk"])
@pytest.mark.parametrize("command", sorted(FAULTS))
def test_multi_file_output_is_whole_or_absent(tmp_path, capsys, monkeypatch, command, fault):
    named = FAULTS[command](monkeypatch, fault)
    out = tmp_path / "new" / "model"
    code = main(_argv(command, out))
    err = capsys.readouterr().err
    if fault == "ctrl-c":
        assert (code, err.splitlines()[-1]) == (130, f"flexarm {command}: interrupted"), err
    else:
        assert code == 2
        line = _last_error(err, command)
        assert line == f"flexarm {command}: error: {out / named}: No space left on device"
    assert list(tmp_path.iterdir()) == []  # no file, no folder made for them, no .part


@pytest.mark.parametrize("fault", ["ctrl-c", "full-disk"])
@pytest.mark.parametrize("command", sorted(FAULTS))
def test_multi_file_output_keeps_the_older_complete_one(tmp_path, capsys, monkeypatch,
                                                        command, fault):
    assert main(_argv(command, tmp_path, other=True)) == 0
    first = sorted(p.name for p in tmp_path.iterdir())
    assert len(first) >= 4, first  # every part of the output, the script or CSV with them
    (tmp_path / "notes.txt").write_text("the user's own file")
    before = _tree(tmp_path)
    FAULTS[command](monkeypatch, fault)
    assert main(_argv(command, tmp_path)) == (130 if fault == "ctrl-c" else 2)
    assert capsys.readouterr().err.strip().splitlines()[-1].startswith(f"flexarm {command}: ")
    assert _tree(tmp_path) == before


def test_lab_refuses_one_file_named_twice(tmp_path, capsys):
    csv = tmp_path / "lab.csv"
    assert main([*LAB, "--modal", str(csv), "-o", str(csv)]) == 2
    line = _last_error(capsys.readouterr().err, "lab")
    assert line == f"flexarm lab: error: {csv}: named twice among the files to write"
    assert list(tmp_path.iterdir()) == []


# --- a full disk under a zip archive: one line, no traceback of a half-closed one ------
@pytest.mark.parametrize("suffix, writer", [
    ("npz", "numpy.lib.format.write_array"),  # inside the zip archive
    ("mat", "pathlib.Path.write_bytes"),
])
def test_full_disk_in_an_export_is_one_line(tmp_path, capfd, monkeypatch, suffix, writer):
    monkeypatch.setattr(writer, _full_disk)
    out = tmp_path / f"arm.{suffix}"
    assert main(["export-arm", "-o", str(out)]) == 2
    gc.collect()  # a half-closed archive would complain when collected
    err = capfd.readouterr().err
    assert err.strip().splitlines() == [f"flexarm export-arm: error: {out}: No space left on "
                                        "device"], err
    assert list(tmp_path.iterdir()) == []


def test_mat_export_is_the_same_bytes_on_every_run(tmp_path, monkeypatch):
    import time

    first, second = tmp_path / "a.mat", tmp_path / "b.mat"
    assert main(["export-arm", "-o", str(first)]) == 0
    real = time.asctime
    monkeypatch.setattr(time, "asctime", lambda *a: real(time.localtime(0)))  # another day
    assert main(["export-arm", "-o", str(second)]) == 0
    assert first.read_bytes() == second.read_bytes()
    from scipy.io import loadmat

    assert loadmat(first)["A"].shape[0] == loadmat(first)["A"].shape[1] > 0


# --- RAPID at depth --------------------------------------------------------------------
@pytest.mark.parametrize("value", [
    "[" * 200_000 + "1" + "]" * 200_000,
    "(" * 200_000 + "1" + ")" * 200_000,
], ids=["brackets", "parentheses"])
def test_deeply_nested_rapid_is_one_line(tmp_path, capsys, value):
    program = tmp_path / "deep.mod"
    program.write_text(f"MODULE Deep\n    CONST num x:={value};\nENDMODULE\n")
    out = tmp_path / "out.mod"
    assert main(["compensate", str(program), "--force", "tool:fz=300N", "-o", str(out)]) == 2
    line = _last_error(capsys.readouterr().err, "compensate")
    assert line.endswith(f"{program}, line 2: brackets nested more than 32 deep (RAPID "
                         "aggregates nest a few levels)"), line
    assert not out.exists()


# --- big measurement files -------------------------------------------------------------
def _many_series(rows):
    """The example's two series repeated 40 times under new labels (``c1_y7``): 80 series
    at two poses."""
    return [[f"{r[0]}{k}", *r[1:]] for k in range(40) for r in rows]


def test_many_series_are_summarised_and_drawn_as_densities(tmp_path, capsys, monkeypatch):
    from flexarm.validation import tolerances
    from flexarm.validation.static import compare, plots, report

    small = dataclasses.replace(tolerances.tol, plot_max_points=20, plot_max_panels=4)
    for module in (compare, plots, report):
        monkeypatch.setattr(module, "tol", small)
    drawn = []
    density = plots._plot_density
    monkeypatch.setattr(plots, "_plot_density", lambda *a: drawn.append(a) or density(*a))
    out = tmp_path / "report"
    assert main(["compare", str(static_csv(tmp_path, _many_series)), "-o", str(out)]) == 0
    text = capsys.readouterr().out
    errors = np.genfromtxt(out / "errors.csv", delimiter=",", names=True, dtype=None,
                           encoding=None)
    assert len(errors) == 80 and "80 series: one row per pose and load direction" in text
    printed = {tuple(ln.split()[:2]): ln.split()[2:] for ln in text.splitlines()
               if ln.split()[:1] in (["c1"], ["c2"])}
    assert sorted(printed) == [("c1", "+y"), ("c2", "+x")]
    for (pose, d), (n, mean_abs, max_abs, relative, max_meas) in printed.items():
        rows = errors[(errors["pose"] == pose) & (errors["dir"] == d)]
        assert int(n) == len(rows) == 40
        assert float(mean_abs) == pytest.approx(rows["mean_abs_mm"].mean(), abs=5e-5)
        assert float(max_abs) == pytest.approx(rows["max_abs_mm"].max(), abs=5e-5)
        assert float(relative) == pytest.approx(rows["relative"].mean(), abs=5e-5)
        assert float(max_meas) == pytest.approx(rows["max_meas_mm"].max(), abs=5e-5)
    assert len(drawn) == 1  # the residual picture is a density
    assert sorted(p.name for p in out.iterdir()) == [
        "deflection_vs_force.png", "errors.csv", "residual_by_pose.png",
        "residual_vs_torque.png", "residuals.csv"]
