# ruff: noqa: T201 - a benchmark prints its figures
"""Benchmark: reading big static measurement files and ``compare`` on them.

A static CSV of N rows is generated in a temporary folder: the header of the shipped
example, series of 10 load steps (the first the reference reading, 0 0 0), the thesis's
configuration 1 for every series, a load along y from 0 to 1800 N, and displacements of
about 0.05 mm with 4 decimals.  Each step runs in its own process, which reports its
wall time and its own peak RSS (``resource.getrusage``), and the RSS right after the
imports, so the step's share is the difference:

* ``read``: :func:`flexarm.validation.read_measurements`;
* ``compare``: :func:`flexarm.validation.workflow.compare` on the E-model (surface mass
  properties: no meshing), as ``flexarm compare`` runs it.

Targets (issue: hostile input and scale): 1e6 rows read and compared in under 10 s and
500 MB.  A step that runs longer than ``--timeout`` is stopped and reported as such.

    python benchmarks/io.py                       # 1e5 and 1e6 rows, read and compare
    python benchmarks/io.py --rows 1e5 --steps read
    python benchmarks/io.py --timeout 120
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

_CHILD = (
    "import resource, sys, time\n"
    "from flexarm.validation import read_measurements\n"
    "from flexarm.validation.workflow import compare\n"
    "base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss\n"
    "t0 = time.perf_counter()\n"
    "if sys.argv[1] == 'read':\n"
    "    n = read_measurements(sys.argv[2]).disp.shape[0]\n"
    "else:\n"
    "    n = compare(sys.argv[2]).predicted.shape[0]\n"
    "dt = time.perf_counter() - t0\n"
    "print('RESULT', n, dt, base, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)\n"
)


def write_static_csv(path: Path, n_rows: int, seed: int = 0) -> float:
    """Write ``n_rows`` static rows to ``path``; returns the file size [MB]."""
    from flexarm.validation import example_path

    head = [ln for ln in Path(example_path("static")).read_text().splitlines()
            if ln.startswith("#") or ln.startswith("series")]
    i = np.arange(n_rows)
    d = np.random.default_rng(seed).normal(size=(n_rows, 3)) * 0.05
    d[i % 10 == 0] = 0.0  # the reference reading of each series
    step = i % 10
    with open(path, "w") as f:
        f.write("\n".join(head) + "\n")
        for start in range(0, n_rows, 100_000):  # a chunk at a time: bounded memory
            s = slice(start, min(start + 100_000, n_rows))
            f.write("".join(
                f"s{k // 10}, {j}, 0, 52, -19, 12, -15, -11, 0, {200 * j}, 0, "
                f"{a:.4f}, {b:.4f}, {c:.4f}, 0.015\n"
                for k, j, (a, b, c) in zip(i[s], step[s], d[s], strict=True)))
    return path.stat().st_size / 1e6


def run_step(step: str, path: Path, timeout: float) -> str:
    """One line: rows, wall time [s], peak RSS and its share above the imports [MB]."""
    try:
        done = subprocess.run([sys.executable, "-c", _CHILD, step, str(path)],
                              capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return f"{step:>8s}: did not finish in {timeout:.0f} s (stopped)"
    result = [ln for ln in done.stdout.splitlines() if ln.startswith("RESULT")]
    if done.returncode or not result:
        last = (done.stderr.strip().splitlines() or ["no output"])[-1]
        return f"{step:>8s}: failed ({last})"
    _, n, dt, base_kb, peak_kb = result[-1].split()
    return (f"{step:>8s}: {int(n):>9,d} rows in {float(dt):7.2f} s, peak RSS "
            f"{int(peak_kb) / 1024:6.0f} MB ({(int(peak_kb) - int(base_kb)) / 1024:+.0f} MB "
            "above the imports)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rows", default="1e5,1e6", help="file sizes, comma-separated")
    ap.add_argument("--steps", default="read,compare", help="read and/or compare")
    ap.add_argument("--timeout", type=float, default=900.0, help="per step [s]")
    args = ap.parse_args()
    print(f"load average at start: {os.getloadavg()[0]:.1f} (2 cores)")
    with tempfile.TemporaryDirectory() as tmp:
        for n in (int(float(r)) for r in args.rows.split(",")):
            path = Path(tmp) / f"static_{n}.csv"
            t0 = time.perf_counter()
            mb = write_static_csv(path, n)
            print(f"{n:,d} static rows: {mb:.1f} MB file (written in "
                  f"{time.perf_counter() - t0:.1f} s)")
            for step in args.steps.split(","):
                print(run_step(step.strip(), path, args.timeout), flush=True)
    print(f"load average at end: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
