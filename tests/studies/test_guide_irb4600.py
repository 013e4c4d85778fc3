"""The guide's IRB 4600 block (``docs/guides/own_robot.md``, "Bring your own robot: the
ABB IRB 4600 from its published URDF") run as written: its commands are read from the
page, its variables expanded (paths relative to the repository, as the page is read),
each command run in a temporary folder, and what it wrote and printed checked.

Slow: the block as written (the robot's own 30 mm mesh, the full-FE reference, a
60 x 60 map).  Default suite: the same commands at a coarse edge and a 7 x 7 map, the
page's figures checked where they do not depend on the mesh.
"""

from __future__ import annotations

import csv
import re
import shlex
from pathlib import Path

import pytest

from ..cli_run import run_cli
from ..irb4600 import URDF

pytestmark = pytest.mark.filterwarnings("ignore:.*placeholder stiffness")

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "guides" / "own_robot.md"
HEADING = "## Bring your own robot: the ABB IRB 4600 from its published URDF"
#: what the coarse variant adds to each command (the edge where Gmsh still puts six nodes
#: on the wrist seats; see tests/irb4600.py)
COARSE = {"build": ["--mesh-size", "0.06"], "show-regions": ["--mesh-size", "0.06"],
          "modes": ["--mesh-size", "0.06"], "compliance": ["--mesh-size", "0.06"],
          "map": ["--mesh-size", "0.06", "--n", "7", "--no-frequencies"],
          "compare-models": ["--mesh-size", "0.06"]}


def guide_block() -> list[list[str]]:
    """The block's ``flexarm`` commands as argument lists, variables expanded (a value
    that names a path relative to the repository made absolute), comments dropped."""
    text = PAGE.read_text()
    start = text.index(HEADING)
    block = re.search(r"```bash\n(.*?)```", text[start:], flags=re.S).group(1)
    variables, commands = {}, []
    for line in block.splitlines():
        words = shlex.split(line, comments=True)
        if not words:
            continue
        if len(words) == 1 and re.fullmatch(r"[A-Z_]+=\S+", words[0]):
            name, value = words[0].split("=", 1)
            variables[name] = str((ROOT / value).resolve()) if (ROOT / value).exists() else value
            continue
        assert words[0] == "flexarm", f"{PAGE}: not a flexarm command: {line}"
        commands.append([re.sub(r"\$(\w+)", lambda m: variables[m.group(1)], w)
                         for w in words[1:]])
    return commands


def test_the_block_reads_as_the_commands_it_documents():
    commands = guide_block()
    assert [c[0] for c in commands] == ["import-urdf", "build", "show-regions", "modes",
                                        "compliance", "map", "compare-models"]
    assert Path(commands[0][1]).resolve() == URDF.resolve()  # $IRB: the shared description


def _run_block(folder: Path, monkeypatch, extra=None) -> dict[str, str]:
    """Every command of the block in ``folder`` (with ``extra`` options per command):
    command -> stdout; each must exit with 0."""
    if not URDF.is_file():
        pytest.skip(f"no IRB 4600 description at {URDF}")
    monkeypatch.chdir(folder)
    printed = {}
    for args in guide_block():
        args = args + (extra or {}).get(args[0], [])
        code, out, err = run_cli(args)
        assert code == 0, f"flexarm {' '.join(args)}: {err}"
        assert "Traceback" not in err
        printed[args[0]] = out
    return printed


def _cb_against_full_fe(folder: Path) -> dict[str, float]:
    """pose -> the largest CB(10) frequency error against the full FE [%] in the CSV
    compare-models wrote."""
    with open(folder / "irb" / "cmp" / "model_comparison.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    return {r["pose"]: float(r["max_f_err_pct"]) for r in rows if r["model"] == "CB(10)"}


def _check_outputs(folder: Path, printed: dict[str, str]) -> None:
    """What every run of the block must show, whatever the mesh."""
    irb = folder / "irb"
    assert (irb / "irb.toml").is_file()
    # the page: "16.2 mm here; solid hull 1,792 kg"
    assert "link CAD hollowed to 16.2 mm walls" in printed["import-urdf"]
    assert re.search(r"solid CAD 179[12]\.\d kg", printed["import-urdf"])
    assert "425.0 kg" in printed["import-urdf"]
    assert len(list((irb / "regions").glob("*.png"))) == 7
    assert "TCP compliance" in printed["compliance"]
    assert (irb / "map" / "map.csv").is_file()
    errors = _cb_against_full_fe(folder)
    assert set(errors) == {"0,52,-19,12,-15,-11", "0,0,66,0,-66,0"}
    # the page: CB(10) within 0.104 % (P1) and 0.052 % (P2) of the full FE
    assert max(errors.values()) < 0.5, errors


def test_the_block_at_a_coarse_mesh(tmp_path, monkeypatch):
    printed = _run_block(tmp_path, monkeypatch, COARSE)
    _check_outputs(tmp_path, printed)


@pytest.mark.slow
def test_the_block_as_written(tmp_path, monkeypatch):
    """The robot's own 30 mm mesh, as the page prints its figures."""
    printed = _run_block(tmp_path, monkeypatch)
    _check_outputs(tmp_path, printed)
    f = [float(v) for v in re.findall(r"^\s*\d+\s+(\d+\.\d+)\s", printed["modes"],
                                      flags=re.M)]
    assert len(f) >= 6 and f[0] > 1.0
