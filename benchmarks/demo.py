# ruff: noqa: T201 - a benchmark prints its figures
"""Benchmark: wall time and peak memory of ``flexarm demo``, cold and warm.

Cold = an empty cache folder (every link meshed by pytetwild, every superelement and the
full-FE reference computed); warm = the same command again with that cache.  Each run is
a separate process reporting its own peak RSS (``resource.getrusage``).  Targets
(of the project): cold <= 5 min, warm <= 20 s on 2 cores.

    python benchmarks/demo.py             # cold + warm in a temporary cache
    python benchmarks/demo.py --warm-only # uses your normal cache
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time

_CHILD = (
    "import resource, sys\n"
    "from flexarm.cli import main\n"
    "rc = main(['demo', '-o', sys.argv[1]])\n"
    "print('PEAK_KB', resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)\n"
    "sys.exit(rc)\n"
)


def run(cache: str | None, out: str) -> tuple[float, float]:
    """Wall time [s] and the demo process's own peak RSS [MB]."""
    env = dict(os.environ)
    if cache:
        env["FLEXARM_CACHE"] = cache
    t0 = time.perf_counter()
    done = subprocess.run([sys.executable, "-c", _CHILD, out], env=env, check=True,
                          capture_output=True, text=True)
    dt = time.perf_counter() - t0
    peak_kb = [int(line.split()[1]) for line in done.stdout.splitlines()
               if line.startswith("PEAK_KB")][-1]
    return dt, peak_kb / 1024.0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--warm-only", action="store_true")
    args = ap.parse_args()
    print(f"load average at start: {os.getloadavg()[0]:.1f} (2 cores)")
    with tempfile.TemporaryDirectory() as tmp:
        cache = None if args.warm_only else os.path.join(tmp, "cache")
        if not args.warm_only:
            dt, mb = run(cache, os.path.join(tmp, "cold"))
            print(f"cold demo: {dt:7.1f} s wall, peak RSS {mb:7.0f} MB (target <= 300 s)")
        dt, mb = run(cache, os.path.join(tmp, "warm"))
        print(f"warm demo: {dt:7.1f} s wall, peak RSS {mb:7.0f} MB (target <= 20 s)")
    print(f"load average at end: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
