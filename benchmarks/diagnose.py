"""Wall time of a full diagnosis: 3 poses x 6 directions x 9 load levels, E-model.

Run: ``python benchmarks/diagnose.py``  (target <= 30 s on 2 cores).
"""

from __future__ import annotations

import time

from flexarm.assembly.emodel import emodel
from flexarm.meshes.demo_arm import load_demo_robot
from flexarm.validation.diagnose import diagnose
from flexarm.validation.effects import parse_effect
from flexarm.validation.lab import LabPlan, parse_dirs, parse_loads, virtual_lab


def main() -> None:
    robot = load_demo_robot()
    arm = emodel(robot, method="surface")
    plan = LabPlan({p: robot.pose(p) for p in ("P1", "P2", "P3")}, parse_loads("0:800:100"),
                   parse_dirs("x,y,z,-x,-y,-z"))
    for effects in (["backlash:j2=0.1mrad"], ["backlash:j2=0.1mrad", "base:k=2e7"]):
        data = virtual_lab(arm, plan, [parse_effect(e) for e in effects], 15e-6, seed=1)
        t0 = time.perf_counter()
        dg = diagnose(arm, data, poses=robot.poses)
        dt = time.perf_counter() - t0
        names = [e.kind for e in dg.accepted]
        print(f"E-model, {len(data.series)} readings, hidden {effects}: {dt:.2f} s, "  # noqa: T201
              f"accepted {names}")
    print("flexible model: not benchmarked (flexarm.assembly.flexible not available yet)")  # noqa: T201


if __name__ == "__main__":
    main()
