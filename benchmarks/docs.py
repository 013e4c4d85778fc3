# ruff: noqa: T201 - a benchmark prints its figures
"""Benchmark: the documentation site built from scratch, as the test command builds it.

The generated API pages (``docs/reference/generated``) and the gallery
(``docs/auto_examples``) are removed first, as ``tests/test_docs.py``'s ``site`` fixture
removes them, so the gallery's examples run and every autosummary page is written again;
then ``python -m sphinx -b html -q -n -W --keep-going docs OUT`` runs in its own process.
Printed: the load average at start and end, the build's wall time, its CPU time (user and
system, from ``resource.getrusage`` of the finished child), its peak RSS and the gallery's
own run time (sphinx-gallery's ``sg_execution_times.rst``).

Target (issue: the docs site in the test command): under 3 minutes of wall time on 2
idle cores, i.e. the CPU time of a serial build well under 180 s.

    python benchmarks/docs.py                  # serial, as the test command builds it
    python benchmarks/docs.py -j 2 --out /tmp/site
"""

from __future__ import annotations

import argparse
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"


def gallery_seconds() -> float | None:
    """The gallery's total run time (s) as sphinx-gallery wrote it, if it did."""
    path = DOCS / "sg_execution_times.rst"
    found = path.is_file() and re.search(r"\*\*(\d+):(\d+\.\d+)\*\* total", path.read_text())
    return 60 * int(found.group(1)) + float(found.group(2)) if found else None


def build(out: Path, jobs: int) -> dict:
    """Build the site from scratch into ``out``; its wall and CPU seconds, peak RSS (MB)."""
    for generated in (DOCS / "reference" / "generated", DOCS / "auto_examples"):
        shutil.rmtree(generated, ignore_errors=True)
    env = dict(os.environ, MPLBACKEND="Agg", PYVISTA_OFF_SCREEN="true")
    cmd = [sys.executable, "-m", "sphinx", "-b", "html", "-q", "-n", "-W", "--keep-going",
           str(DOCS), str(out)]
    if jobs > 1:
        cmd[3:3] = ["-j", str(jobs)]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    run = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=ROOT)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if run.returncode != 0:
        sys.exit(f"docs build failed (exit {run.returncode}): {run.stderr[-2000:]}")
    return {"wall": wall, "user": after.ru_utime - before.ru_utime,
            "sys": after.ru_stime - before.ru_stime, "rss_mb": after.ru_maxrss / 1024}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-j", "--jobs", type=int, default=1,
                    help="sphinx's -j (default 1: serial, as the test command builds)")
    ap.add_argument("--out", type=Path, default=None,
                    help="output folder (default: a temporary folder, removed after)")
    args = ap.parse_args()
    print(f"load average at start: {os.getloadavg()[0]:.1f} (2 cores)")
    with tempfile.TemporaryDirectory() as tmp:
        r = build(args.out or Path(tmp) / "html", args.jobs)
    gallery = gallery_seconds()
    print(f"docs build, -j {args.jobs}: {r['wall']:.1f} s wall, "
          f"{r['user'] + r['sys']:.1f} s CPU (user {r['user']:.1f}, sys {r['sys']:.1f}), "
          f"peak RSS {r['rss_mb']:.0f} MB"
          + (f"; gallery examples {gallery:.1f} s" if gallery is not None else ""))
    print(f"load average at end: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
