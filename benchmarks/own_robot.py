# ruff: noqa: T201 - a benchmark prints its figures
"""Benchmark: a published robot from its URDF to a flexible arm, cold.

The ABB IRB 4600-60/2.05 of ``../shared/data/irb4600`` (ROS-Industrial, Apache-2.0):
``flexarm import-urdf`` (collision hulls hollowed to the wall that makes 425 kg, bearing
seats found on the CAD), then in an empty cache ``flexarm build`` at the robot's mesh
size (target: under 5 min on 2 cores), ``flexarm modes --model cb`` at the thesis's pose
P1, and ``flexarm compare-models`` against the full-FE reference at P1 and P2.  Each
command runs in its own process; wall times and the load average are printed.

    python benchmarks/own_robot.py [--urdf PATH] [--keep DIR]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

URDF = Path(__file__).resolve().parents[2] / "shared/data/irb4600/urdf/irb4600_60_205.urdf"
P1, P2 = "0,52,-19,12,-15,-11", "0,0,66,0,-66,0"


def flexarm(args: list[str], env: dict) -> tuple[float, str]:
    """Wall time [s] and stdout of one ``flexarm`` command in its own process."""
    t0 = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "flexarm.cli", *args], env=env, check=True,
                          capture_output=True, text=True)
    return time.perf_counter() - t0, done.stdout


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--urdf", default=str(URDF))
    ap.add_argument("--keep", default=None, help="folder to keep the robot and cache in")
    args = ap.parse_args()
    print(f"load average at start: {os.getloadavg()[0]:.1f} (2 cores)")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(args.keep or tmp)
        env = dict(os.environ, FLEXARM_CACHE=str(folder / "cache"))
        robot = str(folder / "irb.toml")
        dt, _ = flexarm(["import-urdf", args.urdf, "--total-mass", "425", "--wall", "auto",
                         "-o", robot], env)
        print(f"import-urdf (hollowed to 425 kg, seats found): {dt:6.1f} s")
        dt, out = flexarm(["build", "--robot", robot], env)
        print(f"cold build at the robot's mesh size:            {dt:6.1f} s (target <= 300 s)")
        print("\n".join("  " + line for line in out.splitlines()))
        dt, out = flexarm(["modes", "--robot", robot, "--model", "cb", "--pose", P1, "-n", "6"],
                          env)
        print(f"modes --model cb at P1 (warm):                 {dt:6.1f} s")
        print("\n".join("  " + line for line in out.splitlines()))
        dt, out = flexarm(["compare-models", "--robot", robot, "--poses", f"{P1};{P2}",
                           "-o", str(folder / "compare")], env)
        print(f"compare-models at P1 and P2 with full FE:       {dt:6.1f} s")
        print("\n".join("  " + line for line in out.splitlines() if "wrote" not in line))
    print(f"load average at end: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
