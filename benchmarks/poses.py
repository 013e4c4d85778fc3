"""TCP compliance over a 100×100 (q2, q3) grid: poses per second.

E-model target >= 20,000/s; flexible (CB superelements, ``--flexible``) target >= 1,000/s.
Both use the pose-independent stiffness (``flexarm.assembly.batched``): ``K^-1`` once, only
the TCP map per pose.  ``--frequencies`` also times all eigenfrequencies per pose (``M(q)``
assembled in chunks of ``--chunk`` poses, one inverse-form eigen-solve per pose).

Run: ``python benchmarks/poses.py [--frequencies] [--flexible [--mesh-size 0.04]]``.
Uses the demo arm's mass properties from its CAD surfaces (the timing does not depend on
where they come from).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from flexarm.assembly.analyses import natural_frequencies, tcp_compliance
from flexarm.assembly.emodel import emodel
from flexarm.assembly.maps import grid_poses
from flexarm.robot.demo_arm import load_demo_robot


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--n", type=int, default=100, help="grid points per joint")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--frequencies", action="store_true", help="also time the first eigenfrequency")
    ap.add_argument("--flexible", action="store_true", help="CB flexible model (builds links)")
    ap.add_argument("--mesh-size", type=float, default=None, help="tet edge [m] for --flexible")
    ap.add_argument("--chunk", type=int, default=50, help="poses per M(q) batch (frequencies)")
    args = ap.parse_args()
    robot = load_demo_robot()
    arm = emodel(robot, method="surface")
    if args.flexible:
        from flexarm.assembly.build import BuildOptions
        from flexarm.assembly.flexible import flexible_arm

        arm = flexible_arm(robot, BuildOptions(mesh_size=args.mesh_size))
        print(f"flexible model: {arm.layout['n']} coordinates")  # noqa: T201
    lo, hi = robot.lower, robot.upper
    Q = grid_poses(robot.pose("P1"), (1, 2), np.linspace(lo[1], hi[1], args.n),
                   np.linspace(lo[2], hi[2], args.n)).reshape(-1, 6)
    best = np.inf
    for _ in range(args.repeat):
        t = time.perf_counter()
        tcp_compliance(arm, Q)
        best = min(best, time.perf_counter() - t)
    print(f"TCP compliance: {len(Q)} poses in {best * 1e3:.1f} ms = {len(Q) / best:,.0f} poses/s")  # noqa: T201
    if args.frequencies:
        t = time.perf_counter()
        natural_frequencies(arm, Q, chunk=args.chunk)
        dt = time.perf_counter() - t
        print(f"eigenfrequencies: {len(Q) / dt:,.0f} poses/s")  # noqa: T201


if __name__ == "__main__":
    main()
