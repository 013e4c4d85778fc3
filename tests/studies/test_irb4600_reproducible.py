"""An imported robot is a function of its inputs: the ABB IRB 4600 from its URDF, built
twice in two empty caches, gives the same CB frequencies to the last bit (its links are
meshed by Gmsh under ``model.mesher = "auto"``; fTetWild gave 2.6 % on f4 and 12 % on f8
between two such builds at this mesh size).  The hollowed import says how long its
meshing will take."""

from __future__ import annotations

import re

import numpy as np
import pytest

from ..cli_run import run_cli
from ..irb4600 import COARSE, P1, import_irb

pytestmark = pytest.mark.filterwarnings("ignore:.*placeholder stiffness")

LINKS = ("base_link", "link_1", "link_2", "link_3", "link_4", "link_5", "link_6")


def _table(text: str) -> dict[str, list[str]]:
    """link -> the fields of its row in the table that ``flexarm build`` prints."""
    return {ln.split()[0]: ln.split() for ln in text.splitlines() if ln.split()[:1] and
            ln.split()[0] in LINKS}


def test_two_builds_in_two_empty_caches_give_identical_cb_frequencies(tmp_path, monkeypatch):
    pytest.importorskip("gmsh", exc_type=ImportError)
    toml, _, _ = import_irb(tmp_path)
    assert 'mesher = "auto"' in toml.read_text()
    runs = []
    for cache in ("first", "second"):
        monkeypatch.setenv("FLEXARM_CACHE", str(tmp_path / cache))
        code, out, err = run_cli(["build", "--robot", str(toml), "--mesh-size", str(COARSE)])
        assert code == 0, err
        table = _table(out)
        assert set(table) == set(LINKS)
        assert {row[1] for row in table.values()} == {"gmsh"}, out  # no fTetWild fallback
        code, out, err = run_cli(["modes", "--robot", str(toml), "--model", "cb",
                                  "--mesh-size", str(COARSE), "--pose", P1, "-n", "10"])
        assert code == 0, err
        runs.append((table, np.array([float(f) for f in re.findall(
            r"^\s*\d+\s+(\d+\.\d+)\s", out, flags=re.M)])))
    (first_table, first), (second_table, second) = runs
    assert len(first) == 10
    np.testing.assert_array_equal(first, second)
    for name in LINKS:  # the same elements and fixed-interface frequencies per link
        assert first_table[name][2] == second_table[name][2]
        assert first_table[name][7:] == second_table[name][7:]


def test_hollowing_says_how_long_the_shells_take_to_mesh(tmp_path):
    _, out, _ = import_irb(tmp_path, "--wall", "auto")
    line = next(ln for ln in out.splitlines() if ln.startswith("meshing estimate"))
    n, seconds = (float(v.replace(",", "")) for v in re.findall(
        r"about ([\d,]+) tetrahedra in about (\d+) s", line)[0])
    # gmsh made 52,934 tetrahedra of these shells at 30 mm (2026-11-27): within 2x
    assert 52_934 / 2 < n < 52_934 * 2 and seconds > 0
    assert "(`flexarm build`, auto, 30 mm edge)" in line
