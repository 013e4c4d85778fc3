# ruff: noqa: T201 - a benchmark prints its figures
"""Benchmark: how Craig-Bampton scales with the link size, in core and on PETSc/MPI.

For each size, a Tet10 bar 1.0 x 0.12 x 0.12 m refined in all three directions (so the
factor fills like a 3-D part, not like a chain) is reduced (RBE2 at both ends, 20
modes) by the default in-core path (double-precision factor), in core with a
single-precision factor refined to double accuracy (``single``), and by the PETSc path
on 1 and 2 MPI ranks.  Every
run is its own process (``mpiexec`` for PETSc) that samples its resident memory every
20 ms; rank 0 sums the ranks' samples, so the peaks include every process of the run.
Per stage (``assemble_couple``, ``factorise``, ``constraint_modes``, ``eigen``,
``projection``, ``rest`` = recovery and superelement) it prints wall time and peak RSS
[GB], then the growth exponents ``d log(t) / d log(n)`` between consecutive sizes, and
the memory estimate the reduction checks before it starts.

    python benchmarks/scale.py                          # 0.2M and 0.5M DOF (minutes, ~8 GB)
    python benchmarks/scale.py --dofs 0.05,0.2          # quicker
    python benchmarks/scale.py --paths default,petsc2   # choose paths
    python benchmarks/scale.py --dofs 1.5 --paths single  # a link past the double ceiling
    python benchmarks/scale.py --fit                    # largest link that fits, per path

The PETSc path needs the MPI environment (``bash install.sh --mpi``: ``.venv/mpi``).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
MPI_PYTHON = Path(os.environ.get("FLEXARM_MPI_PYTHON", ROOT / ".venv" / "mpi" / "bin" / "python"))
STAGES = ("assemble_couple", "factorise", "constraint_modes", "eigen", "projection", "rest")
#: path -> (backend, MPI ranks, factor precision)
PATHS = {"default": (None, 0, "double"), "single": (None, 0, "single"),
         "petsc1": ("petsc", 1, "double"), "petsc2": ("petsc", 2, "double")}


def divisions_for(n_dofs: float) -> tuple[int, int, int]:
    """Cells (n, k, k) of the 1.0 x 0.12 x 0.12 bar with about ``n_dofs`` Tet10 DOFs."""
    k = max(2, round((n_dofs / (3 * 8 * 8.33)) ** (1 / 3)))
    n = max(4, round((n_dofs / (3 * (2 * k + 1) ** 2) - 1) / 2))
    return n, k, k


def _rss() -> float:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def worker(div: tuple[int, int, int], backend: str | None, n_modes: int,
           precision: str = "double") -> None:
    """One reduction in this process (every rank under mpiexec); rank 0 prints JSON."""
    from flexarm.fe import MATERIALS
    from flexarm.fe.memory_estimate import estimate_memory
    from flexarm.reduction.reduce import reduce_with_stats
    from flexarm.studies.part_study import bar_link

    mesh, regions = bar_link(1.0, 0.12, div, order=2)
    samples, stop = [], threading.Event()

    def sample():
        while not stop.wait(0.02):
            samples.append((time.perf_counter(), _rss()))

    th = threading.Thread(target=sample, daemon=True)
    t0 = time.perf_counter()
    samples.append((t0, _rss()))
    th.start()
    _, stats = reduce_with_stats(mesh, MATERIALS["steel"], regions, "rbe2", "cb", n_modes,
                                 backend=backend, precision=precision)
    stop.set()
    th.join()
    samples.append((time.perf_counter(), _rss()))
    seconds = dict(stats.seconds) if stats is not None else None
    # stage windows from the (sequential) stage times
    times = []
    if seconds is not None:
        steps = [(k, v) for k, v in seconds.items() if k != "total"]
        steps.append(("rest", seconds["total"] - sum(v for _, v in steps)))
        t = t0
        for k, v in steps:
            times.append((k, t, t + v))
            t += v
    if backend == "petsc":
        from flexarm.fe.petsc_assembly import world

        comm = world()
        times = comm.bcast(times, root=0)
        peaks = [_peak(samples, a, b) for _, a, b in times]
        peaks = comm.reduce(peaks, root=0, op=_sum_lists())
        if comm.Get_rank() != 0:
            return
        ranks = comm.Get_size()
    else:
        peaks = [_peak(samples, a, b) for _, a, b in times]
        ranks = 1
    est = estimate_memory(mesh, 12 + n_modes).in_precision(precision)
    print(json.dumps({"n_dofs": mesh.n_dofs, "ranks": ranks, "total": seconds["total"],
                      "precision": precision,
                      "stages": {k: [b - a, p] for (k, a, b), p in zip(times, peaks, strict=True)},
                      "estimate_gb": est.total_bytes / 1024**3}))


def _peak(samples: list, a: float, b: float) -> float:
    """Largest RSS [bytes] sampled in [a, b], the last sample before ``a`` included."""
    before = [r for s, r in samples if s < a]
    inside = [r for s, r in samples if a <= s <= b]
    return max(inside + before[-1:] or [0.0])


def _sum_lists():
    from mpi4py import MPI

    return MPI.Op.Create(lambda a, b, _t: [x + y for x, y in zip(a, b, strict=True)], commute=True)


def run(path: str, div, n_modes: int) -> dict | None:
    backend, ranks, precision = PATHS[path]
    args = ["--worker", "x".join(map(str, div)), "--modes", str(n_modes),
            "--precision", precision]
    if backend is None:
        cmd = [sys.executable, __file__, *args]
    else:
        if not MPI_PYTHON.exists():
            print(f"  {path}: skipped ({MPI_PYTHON} missing: bash install.sh --mpi)")
            return None
        cmd = ["mpiexec", "-n", str(ranks), str(MPI_PYTHON), __file__, *args, "--petsc"]
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if proc.returncode != 0:
        # the worker's own one-line error, not the banner mpiexec prints after it
        lines = proc.stderr.strip().splitlines()
        why = next((ln for ln in reversed(lines) if "Error:" in ln), "")
        if not why:  # killed: mpiexec's banner names the signal
            why = next((ln.strip() for ln in lines if "signal" in ln or "Killed" in ln),
                       lines[-1] if lines else f"exit code {proc.returncode}")
            if "signal 9" in why or "Killed" in why:
                why += " (out of memory: see dmesg)"
        print(f"  {path}: failed: {why}")
        return None
    return json.loads(proc.stdout.strip().splitlines()[-1])


def report(path: str, res: dict) -> None:
    peak = max(p for _, p in res["stages"].values())
    print(f"  {path:<8s} {res['ranks']} rank(s)  total {res['total']:8.1f} s   peak "
          f"{peak / 1024**3:6.2f} GB   (estimate {res['estimate_gb']:.2f} GB in core, "
          f"{res.get('precision', 'double')} factor)")
    for k in STAGES:
        if k in res["stages"]:
            t, p = res["stages"][k]
            print(f"      {k:<17s} {t:8.2f} s   peak {p / 1024**3:6.2f} GB")


def exponents(path: str, results: list[dict]) -> None:
    for a, b in zip(results, results[1:], strict=False):
        r = math.log(b["n_dofs"] / a["n_dofs"])
        parts = [f"total {math.log(b['total'] / a['total']) / r:.2f}"]
        parts += [f"{k} {math.log(b['stages'][k][0] / a['stages'][k][0]) / r:.2f}"
                  for k in ("factorise", "eigen") if k in a["stages"]]
        pa = max(p for _, p in a["stages"].values())
        pb = max(p for _, p in b["stages"].values())
        parts.append(f"peak memory {math.log(pb / pa) / r:.2f}")
        print(f"  {path} {a['n_dofs']} -> {b['n_dofs']} DOF: time ~ n^x with x = "
              + ", ".join(parts))


def largest_that_fits(n_modes: int) -> None:
    """The largest bar of this family whose memory estimate fits, per factor precision.

    Bisection on the size with the estimate the reduction itself checks (METIS analysis
    of the node graph: seconds), against the memory available now.
    """
    from flexarm.fe.memory_estimate import available_memory, estimate_memory
    from flexarm.studies.part_study import bar_link

    avail = available_memory()
    print(f"available now: {avail / 1024**3:.1f} GB")
    for precision in ("double", "single"):
        lo, hi = 0.5e6, 3e6
        while hi / lo > 1.05:
            mid = math.sqrt(lo * hi)
            mesh, _ = bar_link(1.0, 0.12, divisions_for(mid), order=2)
            est = estimate_memory(mesh, 12 + n_modes).in_precision(precision)
            lo, hi = (mid, hi) if est.total_bytes <= avail else (lo, mid)
        mesh, _ = bar_link(1.0, 0.12, divisions_for(lo), order=2)
        est = estimate_memory(mesh, 12 + n_modes).in_precision(precision)
        print(f"  {precision} factor: largest bar about {mesh.n_dofs / 1e6:.2f}M DOF "
              f"{divisions_for(lo)}: estimate {est.total_bytes / 1024**3:.1f} GB "
              f"(factor {est.factor_bytes / 1024**3:.1f} GB)", flush=True)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--dofs", default="0.2,0.5", help="sizes in millions of DOF")
    p.add_argument("--paths", default="default,petsc1,petsc2")
    p.add_argument("--modes", type=int, default=20)
    p.add_argument("--worker", default=None, help=argparse.SUPPRESS)
    p.add_argument("--petsc", action="store_true", help=argparse.SUPPRESS)
    p.add_argument("--precision", default="double", help=argparse.SUPPRESS)
    p.add_argument("--fit", action="store_true",
                   help="only print the largest bar whose estimate fits, per precision")
    args = p.parse_args()
    if args.worker:
        worker(tuple(int(v) for v in args.worker.split("x")), "petsc" if args.petsc else None,
               args.modes, args.precision)
        return
    if args.fit:
        largest_that_fits(args.modes)
        return
    print(f"load average at start: {os.getloadavg()}", flush=True)
    paths = [s.strip() for s in args.paths.split(",")]
    results = {k: [] for k in paths}
    for size in (float(s) * 1e6 for s in args.dofs.split(",")):
        div = divisions_for(size)
        print(f"Tet10 bar, {div} cells (target {size / 1e6:g}M DOF), {args.modes} modes",
              flush=True)
        for path in paths:
            res = run(path, div, args.modes)
            if res is not None:
                report(path, res)
                results[path].append(res)
    for path in paths:
        exponents(path, results[path])
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
