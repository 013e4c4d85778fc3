"""Time to compensate a 1,000-target program on the E-model and on the CB model.

The program is a face-milling zigzag for the demo arm: 1,000 ``MoveL`` targets 10 mm
apart in a 300 x 300 mm field 500 mm above the base, the spindle (150 mm out of the
flange) pointing down, under a constant 300 N tool-frame force.  Each model is built
first (timed apart: the CB links come from the superelement cache after the first run),
then :func:`flexarm.studies.compensation.compensate` runs end to end: IK along the
sampled path, the fixed point over all targets, the limits, the rewritten module and the
predicted paths before and after.  Target: under 5 s on 2 cores.  The same 1,000 poses
as a CSV (``target, x_mm, y_mm, z_mm, qw, qx, qy, qz``, read as the flange: a
program without the spindle's tooldata) are compensated too, on the E-model: reading
the file and finding each pose's configuration comes on top.

Run: ``python benchmarks/compensate.py`` (``OMP_NUM_THREADS=1`` on a shared machine);
``--models emodel`` for the E-model only.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from flexarm.assembly.arm import ArmSpec, build_arm
from flexarm.robot.demo_arm import load_demo_robot
from flexarm.robot.ik import ik
from flexarm.robot.ik_path import TOOL0, rapid_conf, target_frames
from flexarm.studies.compensation import compensate

N_TARGETS = 1000
DOWN = (0.0, 0.0, 1.0, 0.0)  # tool0 z along -z of the base


def program(path: Path, n: int = N_TARGETS) -> Path:
    """A zigzag of ``n`` MoveL targets (10 mm apart, rows 300 mm long) written as RAPID."""
    robot = load_demo_robot()
    spindle = np.eye(4)
    spindle[2, 3] = 0.15
    chain = replace(robot.chain, tool=TOOL0 @ spindle)
    per_row = 31
    rows = -(-n // per_row)
    pts = []
    for r in range(rows):
        xs = np.linspace(1100.0, 1400.0, per_row)
        pts += [(x, -150.0 + 300.0 * r / max(rows - 1, 1), 500.0)
                for x in (xs if r % 2 == 0 else xs[::-1])]
    pts = np.array(pts[:n])
    T = target_frames(pts, np.tile(DOWN, (n, 1)))
    q = np.radians([0, 30, 0, 0, 60, 0])
    lines = ["MODULE Zigzag",
             "    PERS tooldata tSpindle:=[TRUE,[[0,0,150],[1,0,0,0]],"
             "[20,[0,0,75],[1,0,0,0],0,0,0]];"]
    for k in range(n):
        q = ik(chain, T[k], q_near=q, lower=robot.lower, upper=robot.upper)
        c = rapid_conf(chain, q)
        x, y, z = pts[k]
        lines.append(f"    CONST robtarget p{k}:=[[{x:.3f},{y:.3f},{z:.3f}],[0,0,1,0],"
                     f"[{c[0]},{c[1]},{c[2]},{c[3]}],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];")
    lines.append("    PROC main()")
    lines.append("        MoveJ p0,v100,fine,tSpindle\\WObj:=wobj0;")
    lines += [f"        MoveL p{k},v20,z1,tSpindle\\WObj:=wobj0;" for k in range(1, n)]
    lines += ["    ENDPROC", "ENDMODULE", ""]
    path.write_text("\n".join(lines))
    return path


def poses_csv(path: Path, n: int = N_TARGETS) -> Path:
    """The zigzag's positions and orientation as a CSV of poses."""
    mod = program(path.with_suffix(".mod"), n)
    rows = [line.split(":=[[")[1].split("],[")[:2] for line in mod.read_text().splitlines()
            if "CONST robtarget" in line]
    path.write_text("target,x_mm,y_mm,z_mm,qw,qx,qy,qz\n"
                    + "".join(f"p{k},{p},{q}\n" for k, (p, q) in enumerate(rows)))
    return path


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", default="emodel,cb")
    args = ap.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f}")  # noqa: T201
    robot = load_demo_robot()
    with tempfile.TemporaryDirectory() as tmp:
        mod = program(Path(tmp) / "zigzag.mod")
        for model in args.models.split(","):
            t0 = time.perf_counter()
            arm = build_arm(robot, ArmSpec(model)).model
            t1, c1 = time.perf_counter(), time.process_time()
            res = compensate(mod, robot, "tool:fx=300", spec=ArmSpec(model), arm=arm)
            t2, c2 = time.perf_counter(), time.process_time()
            before = max(r.peak for r in res.runs_before)
            after = max(r.peak for r in res.runs_after)
            print(f"{ArmSpec(model).label:8s} build {t1 - t0:6.2f} s, compensate "  # noqa: T201
                  f"{len(res.shifts)} targets {t2 - t1:6.2f} s wall, {c2 - c1:6.2f} s cpu "
                  f"({res.iterations} "
                  f"iterations); peak deviation {before * 1e3:.3f} -> {after * 1e3:.4f} mm")
            if model == "emodel":
                table = poses_csv(Path(tmp) / "zigzag.csv")
                c0, t0 = time.process_time(), time.perf_counter()
                res = compensate(table, robot, "tool:fx=300", spec=ArmSpec(model), arm=arm)
                t1, c1 = time.perf_counter(), time.process_time()
                print(f"{'':8s} from a CSV of {len(res.shifts)} poses: "  # noqa: T201
                      f"{t1 - t0:6.2f} s wall, {c1 - c0:6.2f} s cpu")
    print(f"load average {os.getloadavg()[0]:.2f}")  # noqa: T201


if __name__ == "__main__":
    main()
