# ruff: noqa: T201 - a benchmark prints its figures
"""Benchmark: wall time and peak memory of ``flexarm demo``, cold and warm.

Cold = an empty cache folder (every link meshed by pytetwild, every superelement and the
full-FE reference computed); warm = the same command again with that cache.  Each run is
a separate process (``/usr/bin/time``-style peak RSS from ``resource``).  Targets
(issue 5): cold <= 5 min, warm <= 20 s on 2 cores.

    python benchmarks/demo.py             # cold + warm in a temporary cache
    python benchmarks/demo.py --warm-only # uses your normal cache
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time


def run(cache: str | None, out: str) -> tuple[float, float]:
    env = dict(os.environ)
    if cache:
        env["FLEXARM_CACHE"] = cache
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "flexarm.cli", "demo", "-o", out], env=env, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    dt = time.perf_counter() - t0
    peak_mb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0
    return dt, peak_mb


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
