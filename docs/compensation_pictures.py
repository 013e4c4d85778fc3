"""The pictures of the compensation guide and the README's "Correcting a program", made by
the loop they describe on the thesis's circles (800 N bar push).

The lab arm is the demo arm with joint stiffness errors of +-30 % and a hidden joint-2
backlash of 0.1 mrad.  Its static series are diagnosed (the API of ``flexarm diagnose
--apply``); the appendix-B module is compensated with the nominal and with the identified
robot file (``flexarm compensate --split 30``) and each program is run in the lab
(:func:`flexarm.studies.compensation.measure_program`), and the measured paths go through
``flexarm history``'s function.  Writes ``docs/images/compensation_history.png`` (what
``flexarm history`` draws: RMS and peak radial deviation of each circle at each step of
the loop, and Path_30's polar deviation at each step) and
``docs/images/compensation_path30.png`` (the picture ``flexarm compensate`` writes, for
Path_30 with the identified robot).

Run: ``python docs/compensation_pictures.py`` (about half a minute); ``--out DIR`` writes
elsewhere.
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

from flexarm.robot.demo_arm import load_demo_robot
from flexarm.robot.effects import parse_effect
from flexarm.studies.compensation import BallBar, compensate, loaded_arm, measure_program
from flexarm.studies.compensation.lab.history import path_history
from flexarm.studies.contact.loaded_circle import THESIS_RAPID
from flexarm.validation.lab.virtual_lab import run_lab
from flexarm.validation.workflow import run_diagnosis

HIDDEN = ("stiffness:j1=1.3", "stiffness:j2=0.7", "stiffness:j3=1.3", "stiffness:j4=0.7",
          "stiffness:j5=1.3", "stiffness:j6=0.7", "backlash:j2=0.1mrad")
PROCS = ("Path_30", "Path_40", "Path_50")


def make_pictures(out: Path, force: float = 800.0, seed: int = 1) -> list[Path]:
    """Run the loop and write the two pictures into ``out``; returns their paths."""
    out.mkdir(parents=True, exist_ok=True)
    robot = load_demo_robot()
    hidden = [parse_effect(e) for e in HIDDEN]
    identified = run_diagnosis(run_lab(robot, hidden, seed=seed).data, robot).updated_robot()
    truth = loaded_arm(robot, hidden)
    bar = BallBar(force)
    steps = {"programmed": measure_program(truth, robot, THESIS_RAPID, bar, PROCS, seed=seed)}
    with tempfile.TemporaryDirectory() as tmp:
        for label, model in (("compensated, nominal model", robot),
                             ("compensated, identified model", identified)):
            res = compensate(THESIS_RAPID, model, bar, procs=PROCS, split_mm=30)
            path = Path(tmp) / "c.mod"
            res.write_module(path)
            steps[label] = measure_program(truth, robot, path, bar, PROCS, res.pivots,
                                           reference=THESIS_RAPID, seed=seed + 1)
        picture = out / "compensation_path30.png"
        res = compensate(THESIS_RAPID, identified, bar, procs=["Path_30"], split_mm=30)
        res.write_plot(picture)
        files, labels = [], []
        for k, (label, lab) in enumerate(steps.items()):
            files += lab.write(Path(tmp) / f"step{k}.csv")  # one path CSV per circle
            labels += [label] * len(lab.runs)
        history = path_history(files, THESIS_RAPID, labels)
        print(history.text())  # noqa: T201
        drawn = history.write_plot(out / "compensation_history.png")
    return [drawn, picture]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(Path(__file__).parent / "images"))
    for path in make_pictures(Path(ap.parse_args().out)):
        print(f"wrote {path}")  # noqa: T201


if __name__ == "__main__":
    main()
