# ruff: noqa: T201 - a benchmark prints its figures
"""Benchmark: reading big static measurement files and ``compare`` on them.

A static CSV of N rows is generated in a temporary folder: the header of the shipped
example, series of 10 load steps (the first the reference reading, 0 0 0), the thesis's
configuration 1 for every series, a load along y from 0 to 1800 N, and displacements of
about 0.05 mm with 4 decimals, drawn anew on every run (so that no picture comes from
the picture cache).  Each step runs in its own process, which reports its wall time and
its own peak RSS (``resource.getrusage``), and the RSS right after the imports:

* ``read``: :func:`flexarm.validation.read_measurements`;
* ``compare``: :func:`flexarm.validation.workflow.compare` on the E-model (surface mass
  properties: no meshing), as ``flexarm compare`` runs it;
* ``compare-o``: the same and its report folder (``compare -o``: errors and residual
  tables, three pictures).

Targets (issue: hostile input and scale, on 2 cores): 1e6 rows read in at most 10 s and
500 MB; ``compare -o`` on 1e6 rows in at most 60 s and 1.5 GB (peak RSS).  A step that
runs longer than ``--timeout`` is stopped and reported as such.

Then a RAPID module of ``--rapid-mb`` MB (60,000 robtargets, then procedures of 200
``MoveL`` each, one in ten through ``Offs``) is read with
:func:`flexarm.robot.formats.rapid.read_rapid` (80 s and 1.8 GB for 25 MB before the
reader streamed its tokens).

    python benchmarks/io.py                       # 1e5 and 1e6 rows, every step, 25 MB RAPID
    python benchmarks/io.py --rows 1e5 --steps read --rapid-mb 0
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
    "import resource, sys, tempfile, time\n"
    "from flexarm.validation import read_measurements\n"
    "from flexarm.validation.workflow import compare\n"
    "base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss\n"
    "t0 = time.perf_counter()\n"
    "if sys.argv[1] == 'read':\n"
    "    n = read_measurements(sys.argv[2]).disp.shape[0]\n"
    "else:\n"
    "    cmp = compare(sys.argv[2])\n"
    "    n = cmp.predicted.shape[0]\n"
    "    if sys.argv[1] == 'compare-o':\n"
    "        cmp.write(tempfile.mkdtemp(dir=sys.argv[3]))\n"
    "dt = time.perf_counter() - t0\n"
    "print('RESULT', n, dt, base, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)\n"
)
_RAPID_CHILD = (
    "import resource, sys, time\n"
    "from flexarm.robot.formats.rapid import read_rapid\n"
    "base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss\n"
    "t0 = time.perf_counter()\n"
    "n = sum(len(p.motions) for p in read_rapid(sys.argv[1]).procedures.values())\n"
    "dt = time.perf_counter() - t0\n"
    "print('RESULT', n, dt, base, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)\n"
)
#: step -> (rows, seconds, MB): the issue's targets
TARGETS = {"read": (1_000_000, 10.0, 500.0), "compare-o": (1_000_000, 60.0, 1500.0)}


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


def write_rapid_module(path: Path, mb: float, n_targets: int = 60_000, seed: int = 0) -> int:
    """Write a RAPID module of about ``mb`` MB; returns its number of Move instructions."""
    rng = np.random.default_rng(seed)
    lines = ["MODULE Big"]
    lines += [f"    CONST robtarget p{i}:=[[{1000 + i % 500}.5,{-200 + i % 300}.25,"
              f"{800 + i % 100}.125],[0.707106781,0,0.707106781,0],[0,0,0,0],"
              "[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];" for i in range(n_targets)]
    size, moves, k = sum(len(ln) + 1 for ln in lines), 0, 0
    while size < mb * 1e6:
        proc = [f"    PROC Path_{k}()"]
        for j, i in enumerate(rng.integers(0, n_targets, 200)):
            target = f"Offs(p{i},10,0,-5)" if j % 10 == 0 else f"p{i}"
            proc.append(f"        MoveL {target},v100,z10,tool0\\WObj:=wobj0;")
        proc.append("    ENDPROC")
        lines += proc
        size += sum(len(ln) + 1 for ln in proc)
        moves, k = moves + 200, k + 1
    path.write_text("\n".join(lines + ["ENDMODULE"]) + "\n")
    return moves


def run_step(step: str, path: Path, timeout: float) -> str:
    """One line: rows, wall time [s], peak RSS and its share above the imports [MB], and
    the target where the issue sets one."""
    with tempfile.TemporaryDirectory() as scratch:
        child = [_RAPID_CHILD, str(path)] if step == "rapid" else [_CHILD, step, str(path),
                                                                    scratch]
        try:
            done = subprocess.run([sys.executable, "-c", *child], capture_output=True,
                                  text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            return f"{step:>9s}: did not finish in {timeout:.0f} s (stopped)"
    result = [ln for ln in done.stdout.splitlines() if ln.startswith("RESULT")]
    if done.returncode or not result:
        last = (done.stderr.strip().splitlines() or ["no output"])[-1]
        return f"{step:>9s}: failed ({last})"
    _, n, dt, base_kb, peak_kb = result[-1].split()
    n, dt, peak = int(n), float(dt), int(peak_kb) / 1024
    what = "Move instructions" if step == "rapid" else "rows"
    line = (f"{step:>9s}: {n:>9,d} {what} in {dt:7.2f} s, peak RSS {peak:6.0f} MB "
            f"({(int(peak_kb) - int(base_kb)) / 1024:+.0f} MB above the imports)")
    rows, seconds, mb = TARGETS.get(step, (-1, 0.0, 0.0))
    if n == rows:
        met = dt <= seconds and peak <= mb
        line += f"; target {seconds:g} s, {mb:g} MB: {'met' if met else 'NOT met'}"
    return line


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rows", default="1e5,1e6", help="file sizes, comma-separated")
    ap.add_argument("--steps", default="read,compare,compare-o",
                    help="read, compare and/or compare-o")
    ap.add_argument("--timeout", type=float, default=900.0, help="per step [s]")
    ap.add_argument("--rapid-mb", type=float, default=25.0,
                    help="size of the RAPID module to read [MB] (0: none)")
    args = ap.parse_args()
    print(f"load average at start: {os.getloadavg()[0]:.1f} (2 cores)")
    seed = time.time_ns() % 2**32
    with tempfile.TemporaryDirectory() as tmp:
        for n in (int(float(r)) for r in args.rows.split(",")):
            path = Path(tmp) / f"static_{n}.csv"
            t0 = time.perf_counter()
            mb = write_static_csv(path, n, seed)
            print(f"{n:,d} static rows: {mb:.1f} MB file (seed {seed}, written in "
                  f"{time.perf_counter() - t0:.1f} s)")
            for step in args.steps.split(","):
                print(run_step(step.strip(), path, args.timeout), flush=True)
            path.unlink()
        if args.rapid_mb > 0:
            path = Path(tmp) / "big.mod"
            t0 = time.perf_counter()
            moves = write_rapid_module(path, args.rapid_mb)
            print(f"RAPID module: {path.stat().st_size / 1e6:.1f} MB, {moves:,d} Move "
                  f"instructions (written in {time.perf_counter() - t0:.1f} s)")
            print(run_step("rapid", path, args.timeout), flush=True)
    print(f"load average at end: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
