"""The README's Python API blocks run as written, in order, in one namespace, and print what
their comments promise."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[1] / "README.md"


def _api_blocks() -> list[str]:
    text = README.read_text()
    section = text[text.index("## Python API"):text.index("## Solver backends")]
    return re.findall(r"```python\n(.*?)```", section, flags=re.S)


def test_the_api_section_has_the_main_jobs():
    code = "\n".join(_api_blocks())
    for job in ("part_modes", "reduce_part", "build_arm", "compliance_report", "run_lab",
                "compare(", "run_diagnosis", "run_circle", "run_chatter"):
        assert job in code, job


def test_the_api_blocks_run(capsys):
    namespace: dict = {}
    for block in _api_blocks():
        exec(compile(block, str(README), "exec"), namespace)  # noqa: S102 - our own README
    printed = capsys.readouterr().out
    assert namespace["clamped"].freq_hz[:3] == pytest.approx([41.84, 41.85, 259.3], rel=2e-3)
    assert namespace["se"].n_dofs == 22
    assert namespace["report"].weakest == "y"
    assert namespace["report"].deflection[1] * 1e3 == pytest.approx(6.2, abs=0.05)
    assert "ACCEPTED: joint 2 backlash" in printed
    assert namespace["chatter"].kcb == 5e5
