"""Universal files as other tools write them (``../shared/data/uff``, see its README):
each goes through ``ema`` and ``compare`` with ``--pose``/``--tcp-node`` as needed, and
gives either the modes the README lists or one line that names the fix.  A file without
a pose is refused without ``--pose``, and with it reads as the same data with the mark.
"""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import numpy as np
import pytest

from flexarm.cli import main

CORPUS = Path(__file__).resolve().parents[4] / "shared/data/uff"
FILES = sorted(p for p in CORPUS.rglob("*") if p.suffix.lower() in (".uff", ".unv"))
#: The free-free beam SDynPy wrote: bending modes in Z [Hz], all at 1 % damping.
BEAM = (51.885, 143.025, 280.398, 463.561, 692.620)
#: Words of a refusal that says what to do.
FIX = re.compile(r"--pose|--response|--tcp-node|points\.csv|export|measure|give|flexarm ema")


def _run(*argv) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def _refused_with_a_fix(code: int, err: str) -> None:
    lines = [line for line in err.splitlines() if line.strip()]
    assert code == 2 and len(lines) == 1, err
    assert FIX.search(lines[0].split(": error: ", 1)[-1]), lines[0]  # not in the prefix
    assert "Traceback" not in err


@pytest.mark.skipif(not FILES, reason=f"no universal files at {CORPUS}")
@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
def test_each_file_gives_its_modes_or_one_line_that_names_the_fix(path, tmp_path):
    code, out, err = _run("ema", path, "--pose", "0,0,0,0,0,0", "-o", tmp_path / "m.csv")
    if path.name == "beam_accel.unv":
        assert code == 0, err
        rows = [line.split() for line in out.splitlines() if line.startswith("measured")]
        f, zeta = np.array([[float(r[2]), float(r[3])] for r in rows]).T
        assert np.allclose(f, BEAM, rtol=1e-3) and np.allclose(zeta, 1.0, rtol=0.05)
    else:
        _refused_with_a_fix(code, err)
    code, out, err = _run("compare", path, "--pose", "P1", "--tcp-node", "1")
    if code != 0:
        _refused_with_a_fix(code, err)


@pytest.mark.skipif(not FILES, reason=f"no universal files at {CORPUS}")
def test_a_file_without_a_pose_is_refused_and_read_at_the_given_one(tmp_path):
    code, _, err = _run("ema", CORPUS / "sdynpy_beam/beam_accel.unv", "-o", tmp_path / "m.csv")
    _refused_with_a_fix(code, err)
    assert "--pose" in err


def test_a_lab_file_without_its_mark_compares_alike_at_the_given_pose(tmp_path):
    """``lab`` writes its universal file with pose marks; the same file with the marks
    blanked out is refused without ``--pose`` and, with ``--pose P1``, gives the same
    comparison to 1e-12."""
    from flexarm.validation.workflow import compare

    static, uff = tmp_path / "s.csv", tmp_path / "lab.uff"
    assert _run("lab", "--poses", "P1", "--loads", "0:100:100", "--dirs", "z", "--modal", uff,
                "-o", static)[0] == 0
    text = uff.read_text()
    bare = tmp_path / "bare.uff"
    bare.write_text(re.sub(r"flexarm pose=\S+ q_deg=\S+", lambda m: " " * len(m.group(0)),
                           text))
    _refused_with_a_fix(*_run("compare", bare)[::2])
    marked = compare(uff).poses
    given = compare(bare, pose="P1").poses
    assert [pc.pose for pc in marked] == [pc.pose for pc in given] == ["P1"]
    for a, b in zip(marked, given, strict=True):
        assert np.allclose(a.f_meas, b.f_meas, rtol=1e-12, atol=0)
        assert np.allclose(a.f_model, b.f_model, rtol=1e-12, atol=0)
        assert np.allclose(a.mac, b.mac, rtol=0, atol=1e-12)
        assert a.model.tolist() == b.model.tolist()
