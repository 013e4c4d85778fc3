"""``benchmarks/demo.py``: the stage clock charges every interval to exactly one stage,
imports and cache reads apart from the stage they happen in."""

from __future__ import annotations

import runpy
import time
from pathlib import Path

import pytest

#: The benchmark's names (the script run as a module, not as ``__main__``).
BENCH = runpy.run_path(str(Path(__file__).parents[2] / "benchmarks" / "demo.py"))


class _Ticks:
    """A clock that advances 1 s per reading (wall) and 0.5 s (CPU)."""

    def __init__(self):
        self.n = 0

    def wall(self) -> float:
        self.n += 1
        return float(self.n)

    def cpu(self) -> float:
        return self.n / 2


def test_intervals_go_to_the_innermost_category_then_the_current_stage(monkeypatch):
    ticks = _Ticks()
    monkeypatch.setattr(time, "perf_counter", ticks.wall)
    monkeypatch.setattr(time, "process_time", ticks.cpu)
    clock = BENCH["StageClock"]("start-up")  # each clock reading below is one tick later
    with clock.category("cache reads"):  # start-up 1
        with clock.category("imports"):  # cache reads 1
            pass  # imports 1
    # back in start-up after the cache read (1); a stage's trailing "(...)" note dropped
    clock.stage("arm: Bode plot at P1 (cached)")  # start-up 1
    clock.stage("build: base: superelement from cache")  # Bode 1
    clock.stage("build: frame: superelement from cache")  # build 1, the same stage
    clock.stage("arm: flexible stiffness map over (q2, q3) and mode pictures")  # build 1
    stages = clock.close()  # flexible map 1
    assert list(stages) == ["start-up", "cache reads", "imports", "arm: Bode plot at P1",
                            "build: per link",
                            "arm: flexible stiffness map over (q2, q3) and mode pictures"]
    wall = {k: w for k, (w, _) in stages.items()}
    assert wall == {"start-up": 2.0, "cache reads": 2.0, "imports": 1.0,
                    "arm: Bode plot at P1": 1.0, "build: per link": 2.0,
                    "arm: flexible stiffness map over (q2, q3) and mode pictures": 1.0}
    # nothing is counted twice or lost: the stages add up to the clock's whole span
    assert sum(wall.values()) == 10.0 - 1.0
    assert sum(c for _, c in stages.values()) == pytest.approx((10.0 - 1.0) / 2)


def test_the_accuracy_study_is_split_into_its_references_and_variants():
    clock = BENCH["StageClock"]("start-up")
    lines = ["arm: accuracy study at P1 against the full-FE reference (cached after the first run)",
             "study: full-FE reference at 30 mm (rbe2)", "study: base: full FE model",
             "study: full-FE reference: 46059 DOF in 5.8 s",
             "study: meshing all links at 30 mm (cached)",
             "study: [1/6] 30 mm rbe2 Guyan: 54 DOF, f err 0.67%",
             "study: [2/6] 30 mm rbe2 CB(5): 89 DOF, f err 0.0352%",
             "study: full FE with Tet10 elements at 30 mm (mesh error)",
             "study: full-FE reference at 30 mm (rbe2)", "study: base: full FE model",
             "study: full-FE reference: 282285 DOF in 44.4 s",
             "arm: flexible stiffness map over (q2, q3) and mode pictures"]
    for line in lines:
        clock.stage(line)
    assert list(clock.close()) == [
        "start-up", "arm: accuracy study at P1 against the full-FE reference",
        "study: full-FE reference, Tet4", "study: variants (builds, solves)",
        "study: full-FE reference, Tet10 (mesh error)",
        "arm: flexible stiffness map over (q2, q3) and mode pictures"]
