# ruff: noqa: T201 - a benchmark prints its figures
"""Benchmark: time-domain runs of the arm's Exudyn model, wall time per simulated second.

On the E-model (rigid links) and the CB arm (60 mm mesh, 10 modes per link,
floating-frame reduced-order bodies):

- a TCP hammer pulse at P1 (gravity off), ``--duration`` s with the implicit trapezoidal
  rule at two time steps: steps, wall time of the integration alone and of the whole test
  (build, integration, FFT, FRF), CPU time, integration seconds per simulated second
  (real time = 1), the largest error of the first three peaks against flexarm's modes;
- the loaded circle ``Path_30`` at 100 mm/s and ``Path_20`` as programmed (v1000), gravity
  on, 200 N bar force (two runs each, with and without the force), dt 2 ms: wall time per
  simulated second of motion and the difference from the quasi-static circle.

Needs ``flexarm[mbs]`` and the demo arm's links in the cache (built on first use).

    python benchmarks/exudyn_time.py [--duration 3] [--no-path]
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from flexarm.assembly.arm import ArmSpec, build_arm
from flexarm.robot import load_robot
from flexarm.studies.exudyn.impulse import impulse_test
from flexarm.studies.exudyn.model import ffrf_links
from flexarm.studies.exudyn.path import HOLD, exudyn_circle


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=3.0, help="simulated time [s]")
    ap.add_argument("--no-path", action="store_true", help="only the impulse runs")
    args = ap.parse_args()
    print(f"load average at start: {os.getloadavg()[0]:.1f}")
    robot = load_robot()
    q = robot.pose("P1")
    print(f"{'model':8s} {'dt_s':>7s} {'steps':>6s} {'integrate_s':>11s} {'total_s':>7s} "
          f"{'total_cpu_s':>11s} {'s_per_sim_s':>11s} {'max_peak_err_%':>14s}")
    for spec in (ArmSpec("emodel"), ArmSpec("cb", mesh_size=0.06, n_modes=10)):
        arm = build_arm(robot, spec)
        links = ffrf_links(arm)
        for dt in (1e-3, 5e-4):
            c0, t0 = time.process_time(), time.perf_counter()
            res = impulse_test(arm, q, duration=args.duration, dt=dt, links=links)
            wall, cpu = time.perf_counter() - t0, time.process_time() - c0
            err = 100 * np.abs(res.peaks_hz / res.freq_ours - 1).max()
            print(f"{spec.label:8s} {dt:7.0e} {res.t.size - 1:6d} {res.seconds:11.2f} "
                  f"{wall:7.2f} {cpu:11.2f} {res.seconds / args.duration:11.2f} {err:14.3f}")
    if not args.no_path:
        _paths(robot)
    print(f"load average at end: {os.getloadavg()[0]:.1f}")


def _paths(robot) -> None:
    print(f"{'model':8s} {'path':8s} {'mm/s':>6s} {'motion_s':>8s} {'wall_s':>7s} "
          f"{'s_per_sim_s':>11s} {'vs_static_%':>11s}")
    for spec in (ArmSpec("emodel"), ArmSpec("cb", mesh_size=0.06, n_modes=10)):
        arm = build_arm(robot, spec)
        for proc, speed in (("Path_30", 0.1), ("Path_20", None)):
            res = exudyn_circle(arm, proc=proc, speed=speed)
            sim = 2 * (res.t[-1] + HOLD)  # two runs, each with its hold at the start
            print(f"{spec.label:8s} {proc:8s} {res.speed * 1e3:6.0f} {res.t[-1]:8.2f} "
                  f"{res.seconds:7.1f} {res.seconds / sim:11.2f} {100 * res.error:11.2f}")


if __name__ == "__main__":
    main()
