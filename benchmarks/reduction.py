# ruff: noqa: T201 - a benchmark prints its figures
"""Benchmark: Craig-Bampton of a ~200k-DOF Tet10 link, ours against Exudyn's.

Prints, per step (couple, factorise, constraint modes, eigen-solve, projection), the
wall time and the peak resident memory above the step's start, then the same reduction
by Exudyn's ``FEMinterface.ComputeHurtyCraigBamptonModes`` (RBE2, identical K, M and
interface nodes) with the time ratio and the largest relative difference of the
fixed-interface frequencies.  Not a test.

The distance to the eigen-solve's bound is printed as the right-hand sides solved per
mode found (``solves/k``; 1 is the floor of a shift-invert method), with the factor's
memory as PARDISO reports it.  ``--precision single`` factorises K_ii in single
precision and refines every solve to double accuracy (half the factor's memory).

    python benchmarks/reduction.py                     # ~200k DOF, 30 modes
    python benchmarks/reduction.py --divisions 40x5x5  # quick check (~30k DOF)
    python benchmarks/reduction.py --precision single  # single-precision factor
"""

from __future__ import annotations

import argparse
import os
import threading
import time
from contextlib import contextmanager

import numpy as np

from flexarm.fe import MATERIALS, assemble, factorize, modes, shift_invert
from flexarm.reduction.craig_bampton import craig_bampton_basis
from flexarm.reduction.guyan import constraint_modes, split_blocks
from flexarm.reduction.projection import project
from flexarm.reduction.reduce import coupled_model
from flexarm.studies.part_study import bar_link


def _rss_mb() -> float:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


@contextmanager
def step(name: str, table: list):
    """Time a step and sample its peak RSS above the starting RSS every 10 ms."""
    start = _rss_mb()
    peak = [start]
    stop = threading.Event()

    def sample():
        while not stop.wait(0.01):
            peak[0] = max(peak[0], _rss_mb())

    th = threading.Thread(target=sample, daemon=True)
    th.start()
    t0 = time.perf_counter()
    try:
        yield
    finally:
        dt = time.perf_counter() - t0
        stop.set()
        th.join()
        peak[0] = max(peak[0], _rss_mb())
        table.append((name, dt, peak[0] - start))
        print(f"  {name:<22s} {dt:9.2f} s   peak +{peak[0] - start:8.0f} MB", flush=True)


def ours(model, n_modes: int, table: list, precision: str = "double"):
    n_b = model.coupling.n_boundary
    with step("factorise K_ii", table):
        K_ii, K_ib = split_blocks(model.K, n_b)
        M_ii = split_blocks(model.M, n_b)[0]
        factor = factorize(K_ii, precision=precision)
    with step("constraint modes", table):
        Psi = constraint_modes(factor, K_ib)
    count, inner = [0], factor._solve

    def counted(b):
        count[0] += 1 if b.ndim == 1 else b.shape[1]
        return inner(b)

    factor._solve = counted
    with step("eigen-solve (reuse)", table):
        fixed = modes(K_ii, M_ii, n_modes, eigensolver=shift_invert(0.0), factor=factor)
    memory = f"{factor.memory_bytes / 2**30:.2f} GB" if factor.memory_bytes else "n/a"
    refined = (f", {factor.refinement.steps_per_solve:.1f} refinement steps per solve"
               if factor.refinement else "")
    print(f"  eigen-solve: {count[0]} solves for {n_modes} modes = {count[0] / n_modes:.2f} "
          f"per mode (bound 1); factor ({factor.precision}) {memory}{refined}", flush=True)
    with step("projection", table):
        T = craig_bampton_basis(Psi, fixed.vectors)
        project(model.K, model.M, T)
    return fixed.freq_hz


def exudyn_cb(mesh, K, M, node_lists, n_modes: int):
    from exudyn.FEM import FEMinterface, HCBstaticModeSelection

    fem = FEMinterface()
    fem.nodes = {"Position": np.asarray(mesh.points)}
    fem.stiffnessMatrix = K.tocsr()
    fem.massMatrix = M.tocsr()
    t0 = time.perf_counter()
    fem.ComputeHurtyCraigBamptonModes(
        boundaryNodesList=[list(map(int, n)) for n in node_lists], nEigenModes=n_modes,
        useSparseSolver=True, computationMode=HCBstaticModeSelection.RBE2)
    dt = time.perf_counter() - t0
    freq = np.sort(np.sqrt(np.abs(fem.eigenValues))) / (2 * np.pi)
    return dt, freq


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--divisions", default="88x9x9", help="box cells along x, y, z (Tet10)")
    ap.add_argument("--modes", type=int, default=30)
    ap.add_argument("--no-exudyn", action="store_true")
    ap.add_argument("--precision", default="double", choices=("double", "single"))
    args = ap.parse_args()
    div = tuple(int(v) for v in args.divisions.split("x"))
    mesh, regions = bar_link(1.0, 0.12, div, order=2)
    steel = MATERIALS["steel"]
    print(f"date {time.strftime('%Y-%m-%d %H:%M')}, load average {os.getloadavg()[0]:.1f} "
          "at start (2 shared cores: read the ratio)")
    print(f"Tet10 bar 1.0 x 0.12 x 0.12 m, {div} cells: {mesh.n_tets} tets, "
          f"{mesh.n_dofs} DOF, {args.modes} modes, RBE2 at both ends", flush=True)
    table: list = []
    with step("assemble K, M", table):
        K, M = assemble(mesh, steel)
    with step("select + couple", table):
        model = coupled_model(mesh, steel, regions, "rbe2", matrices=(K, M))
    print(f"  interface nodes: {[int(i.nodes.size) for i in model.interfaces]}, "
          f"interior DOF {model.coupling.n_interior}", flush=True)
    freq = ours(model, args.modes, table, args.precision)
    t_ours = sum(dt for name, dt, _ in table if name != "assemble K, M")
    print(f"ours (couple .. projection): {t_ours:.2f} s; f1..f3 = "
          f"{', '.join(f'{f:.6f}' for f in freq[:3])} Hz", flush=True)
    if args.no_exudyn:
        print(f"load average {os.getloadavg()[0]:.1f} at end")
        return
    import gc

    gc.collect()
    start = _rss_mb()
    t_ex, f_ex = exudyn_cb(mesh, K, M, [i.nodes for i in model.interfaces], args.modes)
    print(f"exudyn ComputeHurtyCraigBamptonModes (RBE2): {t_ex:.2f} s "
          f"(RSS +{_rss_mb() - start:.0f} MB after)")
    print(f"time ratio exudyn / ours: {t_ex / t_ours:.1f}x")
    print(f"largest relative difference of the {args.modes} fixed-interface frequencies: "
          f"{np.max(np.abs(f_ex[: len(freq)] / freq - 1)):.2e}")
    print(f"load average {os.getloadavg()[0]:.1f} at end")


if __name__ == "__main__":
    main()
