# ruff: noqa: T201 - a benchmark prints its figures
"""Benchmark: wall time and peak memory of ``flexarm demo``, cold and warm.

Cold = an empty cache folder (every link meshed by pytetwild, every superelement, the
full-FE reference and every picture computed); warm = the same command again with that
cache.  Memory counts the whole process tree (the demo, its worker process and any
render-probe subprocess): the tree is sampled every 50 ms from ``/proc`` and the
benchmark prints the largest sum of resident sizes seen, and the sum of every process's
own peak (``VmHWM``, an upper bound: the processes need not peak together).  Targets (of
the project): cold <= 5 min; warm <= 10 s on a quiet machine (2 cores).

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
from pathlib import Path

#: Sampling period of the process tree [s].
_PERIOD = 0.05


def _parents() -> dict[int, int]:
    """Parent of every running process (Linux /proc; ``children`` files are not
    available on every kernel)."""
    out = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            # the command name in parentheses may hold spaces: the ppid follows the last ')'
            out[int(stat.parent.name)] = int(stat.read_text().rsplit(")", 1)[1].split()[1])
        except (OSError, IndexError, ValueError):
            continue
    return out


def _tree(pid: int) -> list[int]:
    """``pid`` and all its descendants."""
    kids: dict[int, list[int]] = {}
    for child, parent in _parents().items():
        kids.setdefault(parent, []).append(child)
    todo, seen = [pid], []
    while todo:
        p = todo.pop()
        seen.append(p)
        todo += kids.get(p, [])
    return seen


def _status_kb(pid: int) -> tuple[int, int]:
    """(VmRSS, VmHWM) of ``pid`` [kB]; zeros once it has gone."""
    try:
        fields = dict(line.split(":", 1) for line in
                      Path(f"/proc/{pid}/status").read_text().splitlines() if ":" in line)
    except OSError:
        return 0, 0
    kb = [int(fields.get(k, "0 kB").split()[0]) for k in ("VmRSS", "VmHWM")]
    return kb[0], kb[1]


def run(cache: str | None, out: str) -> tuple[float, float, float]:
    """Wall time [s], peak RSS of the process tree [MB] and the sum of each process's
    own peak RSS [MB] of one ``flexarm demo`` run."""
    env = dict(os.environ)
    if cache:
        env["FLEXARM_CACHE"] = cache
    t0 = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "flexarm.cli", "demo", "-q", "-o", out],
                            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    peak_tree, hwm = 0, {}
    while proc.poll() is None:
        rss = 0
        for pid in _tree(proc.pid):
            now, high = _status_kb(pid)
            rss += now
            hwm[pid] = max(hwm.get(pid, 0), high)
        peak_tree = max(peak_tree, rss)
        time.sleep(_PERIOD)
    dt = time.perf_counter() - t0
    err = proc.stderr.read().decode(errors="replace")
    if proc.returncode:
        raise SystemExit(f"flexarm demo failed ({proc.returncode}):\n{err}")
    return dt, peak_tree / 1024.0, sum(hwm.values()) / 1024.0


def _report(name: str, figures: tuple[float, float, float], target: str) -> None:
    dt, tree, hwm = figures
    print(f"{name} demo: {dt:7.1f} s wall, peak RSS of the process tree {tree:6.0f} MB "
          f"(sum of per-process peaks {hwm:6.0f} MB) (target {target})")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--warm-only", action="store_true")
    args = ap.parse_args()
    print(f"load average at start: {os.getloadavg()[0]:.1f} (2 cores)")
    with tempfile.TemporaryDirectory() as tmp:
        cache = None if args.warm_only else os.path.join(tmp, "cache")
        if not args.warm_only:
            _report("cold", run(cache, os.path.join(tmp, "cold")), "<= 300 s")
        _report("warm", run(cache, os.path.join(tmp, "warm")), "<= 10 s, quiet machine")
    print(f"load average at end: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
