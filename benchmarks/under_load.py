# ruff: noqa: T201 - a benchmark prints its figures
"""Check: the test suite passes, run after run, while other work loads the machine.

CI runs on a busy 2-core machine, so no test may depend on the load or on timing.  This
script starts ``--load`` busy processes (each one spins a core in pure Python, with the
lowest priority, so that the load average rises by about that many), then runs the
README's test command (``python -m pytest -q -m "not slow" -n auto``, or the paths given
after ``--``) ``--runs`` times in a row, and prints, per run, the exit code, the wall
time, the counts pytest reports and the load average.  It ends with ``k/n runs passed``
and exits 1 unless every run passed.

    python benchmarks/under_load.py                    # 5 runs of the default suite, load +4
    python benchmarks/under_load.py --runs 50 -- tests/fe/test_refinement.py
    python benchmarks/under_load.py --load 0 --runs 1  # the suite alone, for comparison

The busy processes are stopped when the script ends (also on Ctrl-C).
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import os
import re
import subprocess
import sys
import time


def _spin() -> None:
    """Keep one core busy until killed."""
    os.nice(19)
    x = 0
    while True:
        x = (x * 1103515245 + 12345) % 2147483648


def _summary(output: str) -> str:
    """pytest's last summary line (``N passed, M skipped in T s``), or its last line."""
    lines = [ln for ln in output.strip().splitlines() if ln.strip()]
    for line in reversed(lines):
        if re.search(r"\d+ (passed|failed|error)", line):
            return line.strip("= ")
    return lines[-1] if lines else "(no output)"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=5, help="test runs in a row (default 5)")
    parser.add_argument("--load", type=int, default=4,
                        help="busy processes started beside the tests (default 4)")
    parser.add_argument("pytest_args", nargs="*",
                        help='after "--": what pytest runs (default: -m "not slow" -n auto)')
    args = parser.parse_args(argv)
    command = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
               *(args.pytest_args or ["-m", "not slow", "-n", "auto"])]
    print(f"load average at start: {os.getloadavg()[0]:.1f} ({os.cpu_count()} cores); "
          f"{args.load} busy processes; command: {' '.join(command[1:])}", flush=True)
    busy = [mp.Process(target=_spin, daemon=True) for _ in range(args.load)]
    for p in busy:
        p.start()
    passed = 0
    try:
        for run in range(1, args.runs + 1):
            t0 = time.perf_counter()
            done = subprocess.run(command, capture_output=True, text=True)
            ok = done.returncode == 0
            passed += ok
            print(f"run {run}/{args.runs}: exit {done.returncode}, "
                  f"{time.perf_counter() - t0:7.1f} s wall, load {os.getloadavg()[0]:.1f}: "
                  f"{_summary(done.stdout)}", flush=True)
            if not ok:
                failed = [ln for ln in done.stdout.splitlines()
                          if ln.startswith(("FAILED", "ERROR"))]
                print("\n".join(f"    {ln}" for ln in failed[:20]), flush=True)
    finally:
        for p in busy:
            p.kill()
    print(f"{passed}/{args.runs} runs passed under a load of +{args.load}")
    return 0 if passed == args.runs else 1


if __name__ == "__main__":
    sys.exit(main())
