# ruff: noqa: T201 - a benchmark prints its figures
"""Benchmark: wall time, CPU time and peak memory of ``flexarm demo``, cold and warm, and
where a warm run's time goes.

Cold = an empty cache folder (every superelement, the full-FE reference, the diagnosis,
the maps and every picture computed; the demo arm's link meshes are shipped files);
warm = the same command again with that cache.  Memory counts the whole process tree (the
demo, its worker process and any render-probe subprocess): the tree is sampled every
50 ms from ``/proc`` and the benchmark prints the largest sum of resident sizes seen, and
the sum of every process's own peak (``VmHWM``, an upper bound: the processes need not
peak together).  CPU time is the tree's (user + system, every process waited for) and
each process's: the busiest one bounds the wall time on an idle machine from below.
Targets (issue 28): cold <= 60 s; warm <= 5 s on 2 idle cores.

The split (``--no-split`` leaves it out) runs the demo once more in one process (``-j 1``,
the steps in order) with a clock on every import, every cache read and every progress
line the demo prints: imports and cache reads are taken out of the stage they happen in,
and each stage runs from its progress line to the next.  A stage's CPU time includes the
subprocesses it waited for (the render probe).  After a cold run it is done twice: cold,
in another empty cache (where a cold run's CPU time goes, step by step: the two-process
run shares these steps out), then warm.  The accuracy study's steps are listed apart
(its Tet4 reference, its variants, its Tet10 reference).

    python benchmarks/demo.py             # cold + warm in a temporary cache, then the splits
    python benchmarks/demo.py --warm-only # uses your normal cache
    python benchmarks/demo.py --warm-only --repeat 3
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from contextlib import contextmanager
from pathlib import Path

#: Sampling period of the process tree [s].
_PERIOD = 0.05
#: The checkout this benchmark belongs to (its ``flexarm`` is the one measured).
_ROOT = Path(__file__).resolve().parents[1]
#: Progress lines of these prefixes come once per link: one stage each.
_PER_ITEM = {"build": "build: per link"}
#: The accuracy study's lines that begin a stage (first match); its other lines (one per
#: link or variant, and results) continue the stage they are in.  Its Tet10 reference
#: announces itself, then prints the same line as the Tet4 one.
_STUDY_STAGES = (("study: full FE with Tet10", "study: full-FE reference, Tet10 (mesh error)"),
                 ("study: full-FE reference at", "study: full-FE reference, Tet4"),
                 ("study: meshing all links", "study: variants (builds, solves)"))


def _proc_stat(pid: int) -> list[str]:
    """Fields of ``/proc/<pid>/stat`` after the command name (state first); [] once gone.
    The command name in parentheses may hold spaces: the fields follow the last ')'."""
    try:
        return (Path("/proc") / str(pid) / "stat").read_text().rsplit(")", 1)[1].split()
    except (OSError, IndexError):
        return []


def _tree(pid: int) -> list[int]:
    """``pid`` and all its descendants (Linux /proc; ``children`` files are not available
    on every kernel)."""
    kids: dict[int, list[int]] = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        fields = _proc_stat(int(stat.parent.name))
        if len(fields) > 1:
            kids.setdefault(int(fields[1]), []).append(int(stat.parent.name))
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


def _cpu_s(pid: int) -> float:
    """User + system CPU time of ``pid`` itself [s] (0 once it has gone)."""
    fields = _proc_stat(pid)
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK") if fields else 0.0


def _env(cache: str | None) -> dict:
    env = dict(os.environ)
    if cache:
        env["FLEXARM_CACHE"] = cache
    return env


def run(cache: str | None, out: str) -> dict:
    """One ``flexarm demo`` run: wall time [s], CPU time of each process [s] (the demo
    first), peak RSS of the tree and the sum of each process's own peak RSS [MB]."""
    t0 = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "flexarm.cli", "demo", "-q", "-o", out],
                            env=_env(cache), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            cwd=_ROOT)
    peak_tree, hwm, cpu = 0, {}, {}
    while proc.poll() is None:
        rss = 0
        for pid in _tree(proc.pid):
            now, high = _status_kb(pid)
            rss += now
            hwm[pid] = max(hwm.get(pid, 0), high)
            cpu[pid] = max(cpu.get(pid, 0.0), _cpu_s(pid))
        peak_tree = max(peak_tree, rss)
        time.sleep(_PERIOD)
    dt = time.perf_counter() - t0
    err = proc.stderr.read().decode(errors="replace")
    if proc.returncode:
        raise SystemExit(f"flexarm demo failed ({proc.returncode}):\n{err}")
    return {"wall": dt, "tree_mb": peak_tree / 1024.0, "hwm_mb": sum(hwm.values()) / 1024.0,
            "cpu": [cpu[pid] for pid in sorted(cpu) if cpu[pid] >= 0.1]}


def _report(name: str, fig: dict, cpu: float, target: str) -> None:
    each = " + ".join(f"{c:.1f}" for c in fig["cpu"])
    print(f"{name} demo: {fig['wall']:6.1f} s wall (load {os.getloadavg()[0]:.1f}) (target "
          f"{target}); {cpu:5.1f} s CPU ({each} s in the processes that ran 0.1 s or more); "
          f"peak RSS of the tree {fig['tree_mb']:4.0f} MB (sum of per-process peaks "
          f"{fig['hwm_mb']:4.0f} MB)")


def _children_cpu() -> float:
    """CPU time [s] of every process this one has waited for, so far."""
    ru = os.times()
    return ru.children_user + ru.children_system


def timed_run(cache: str | None, out: str, name: str, target: str) -> dict:
    """:func:`run` with the process tree's CPU time, reported in one line."""
    before = _children_cpu()
    fig = run(cache, out)
    _report(name, fig, _children_cpu() - before, target)
    return fig


class StageClock:
    """Wall and CPU time per stage, with named categories (imports, cache reads) taken
    out of whatever stage they happen in; a category inside another is charged to the
    inner one.

    Examples
    --------
    >>> clock = StageClock("start-up")
    >>> with clock.category("imports"):
    ...     pass
    >>> clock.stage("build: base: superelement from cache (22 DOF)")
    >>> clock.stage("build: frame: superelement from cache (22 DOF)")
    >>> list(clock.close())
    ['start-up', 'imports', 'build: per link']
    """

    def __init__(self, first: str):
        self._stack = [first]
        self._mark = (time.perf_counter(), _cpu_here())
        self.wall: dict[str, float] = defaultdict(float)
        self.cpu: dict[str, float] = defaultdict(float)

    def _charge(self) -> None:
        now = (time.perf_counter(), _cpu_here())
        top = self._stack[-1]
        self.wall[top] += now[0] - self._mark[0]
        self.cpu[top] += now[1] - self._mark[1]
        self._mark = now

    @contextmanager
    def category(self, name: str):
        """Charge the time inside the block to ``name``."""
        self._charge()
        self._stack.append(name)
        try:
            yield
        finally:
            self._charge()
            self._stack.pop()

    def stage(self, line: str) -> None:
        """A progress line: the stage it names begins now (without a closing note in
        parentheses; per-link and per-variant lines of one kind make one stage)."""
        self._charge()
        head = line.split(":", 1)[0]
        if head == "study":
            name = _study_stage(line, self._stack[0])
        else:
            name = _PER_ITEM.get(head, re.sub(r" \([^()]*\)$", "", line))
        self._stack[0] = name
        self.wall[name] += 0.0  # listed in the order the stages begin
        self.cpu[name] += 0.0

    def close(self) -> dict[str, tuple[float, float]]:
        """``{stage: (wall [s], CPU [s])}`` in the order the stages first ran."""
        self._charge()
        return {k: (self.wall[k], self.cpu[k]) for k in self.wall}


def _cpu_here() -> float:
    """CPU time [s] of this process and of the subprocesses it has waited for."""
    ru = os.times()
    return time.process_time() + ru.children_user + ru.children_system


def _study_stage(line: str, current: str) -> str:
    """The stage a progress line of the accuracy study belongs to (``current`` if it
    begins none; the Tet10 reference's own reference line continues its stage).

    Examples
    --------
    >>> _study_stage("study: full-FE reference at 30 mm (rbe2)", "arm: accuracy study")
    'study: full-FE reference, Tet4'
    >>> _study_stage("study: base: full FE model", "study: full-FE reference, Tet4")
    'study: full-FE reference, Tet4'
    >>> _study_stage("study: full-FE reference at 30 mm (rbe2)",
    ...              "study: full-FE reference, Tet10 (mesh error)")
    'study: full-FE reference, Tet10 (mesh error)'
    """
    for prefix, name in _STUDY_STAGES:
        if line.startswith(prefix):
            return current if current == _STUDY_STAGES[0][1] else name
    return current


def _split_child(out: str) -> None:
    """Run the demo here (``-j 1``, cold or warm as its cache is) with a
    :class:`StageClock` and print its stages as JSON (the last line of stdout)."""
    import builtins

    sys.path.insert(0, str(_ROOT))
    clock = StageClock("start-up (robot files)")
    real_import = builtins.__import__

    def timed_import(*args, **kwargs):
        with clock.category("imports"):
            return real_import(*args, **kwargs)

    builtins.__import__ = timed_import
    from flexarm.fe import cache

    real_read = cache._load_verified
    reads = []

    def timed_read(path, codec):
        with clock.category("cache reads"):
            value = real_read(path, codec)
        reads.append(path.stat().st_size if value is not None else 0)
        return value

    cache._load_verified = timed_read
    from flexarm.studies.demo import run_demo

    run_demo(out, progress=clock.stage, jobs=1)
    stages = clock.close()
    print(json.dumps({"stages": stages, "reads": len(reads), "read_mb": sum(reads) / 1e6}))


def split(cache: str | None, out: str, kind: str = "warm") -> None:
    """Print where a ``kind`` (cold or warm: the state of ``cache``) run's time goes
    (:func:`_split_child` in a fresh process)."""
    run_ = subprocess.run([sys.executable, __file__, "--split-child", out], env=_env(cache),
                          capture_output=True, text=True, cwd=_ROOT)
    if run_.returncode:
        raise SystemExit(f"split run failed ({run_.returncode}):\n{run_.stderr[-2000:]}")
    got = json.loads(run_.stdout.strip().splitlines()[-1])
    stages = got["stages"]
    wall = sum(w for w, _ in stages.values())
    cpu = sum(c for _, c in stages.values())
    print(f"where a {kind} run's time goes (one process, -j 1; load "
          f"{os.getloadavg()[0]:.1f}): {wall:.1f} s wall, {cpu:.1f} s CPU")
    print(f"  {'stage':<66s} {'wall [s]':>8s} {'CPU [s]':>8s}")
    for name, (w, c) in stages.items():
        label = name
        if name == "cache reads":
            label = f"cache reads ({got['reads']} entries, {got['read_mb']:.0f} MB)"
        print(f"  {label[:66]:<66s} {w:8.2f} {c:8.2f}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--warm-only", action="store_true", help="use the normal cache, no cold run")
    ap.add_argument("--repeat", type=int, default=1, help="warm runs (default 1)")
    ap.add_argument("--no-split", action="store_true", help="leave out the stage splits")
    ap.add_argument("--split-child", metavar="OUT", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.split_child:
        _split_child(args.split_child)
        return
    print(f"load average at start: {os.getloadavg()[0]:.1f} (2 cores)")
    with tempfile.TemporaryDirectory() as tmp:
        cache = None if args.warm_only else os.path.join(tmp, "cache")
        if not args.warm_only:
            timed_run(cache, os.path.join(tmp, "cold"), "cold", "<= 60 s")
        for i in range(args.repeat):
            timed_run(cache, os.path.join(tmp, f"warm{i}"), "warm", "<= 5 s, 2 idle cores")
        if not args.no_split:
            if not args.warm_only:
                split(os.path.join(tmp, "cache-split"), os.path.join(tmp, "split-cold"), "cold")
            split(cache, os.path.join(tmp, "split"))
    print(f"load average at end: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
