# ruff: noqa: T201 - a benchmark prints its figures
"""Benchmark: published robots from their URDF to their first flexible modes, cold.

For each robot, in an empty cache and each command in its own process, as a user types
them: ``flexarm import-urdf`` (datasheet mass; the IRB 4600's hulls hollowed to the wall
that makes 425 kg, as in the guide), ``flexarm build`` (links meshed side by side, one
process per core; its table names each link's mesher) and ``flexarm modes --model cb``.
Printed per command: wall time and peak memory (resident set of the command and every
worker process it started, summed, sampled every 0.1 s); per robot the total against the
target of 60 s on 2 cores at load <= 1; the load average at start and end.

    python benchmarks/own_robot.py [--robots irb4600,m20ia,ur10] [--jobs N] [--keep DIR]
                                   [--compare]

``--compare`` adds ``flexarm compare-models`` of the IRB 4600 against its full-FE
reference at the thesis's poses P1 and P2 (the accuracy figures of the guide).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

DATA = Path(__file__).resolve().parents[2] / "shared/data"
P1, P2 = "0,52,-19,12,-15,-11", "0,0,66,0,-66,0"
#: name -> (URDF, import options, pose of the first modes [deg])
ROBOTS = {
    "irb4600": (DATA / "irb4600/urdf/irb4600_60_205.urdf",
                ["--total-mass", "425", "--wall", "auto"], P1),
    "m20ia": (DATA / "robots/fanuc_m20ia/urdf/m20ia.urdf", ["--total-mass", "250"],
              "0,20,-20,0,30,0"),
    "ur10": (DATA / "robots/ur10/urdf/ur10.urdf", ["--total-mass", "28.9"],
             "0,20,-20,0,30,0"),
}
TARGET_S = 60.0


def _tree_rss(pid: int) -> int:
    """Resident set [bytes] of ``pid`` and all its descendants (Linux ``/proc``)."""
    total, todo = 0, [pid]
    while todo:
        p = todo.pop()
        try:
            with open(f"/proc/{p}/status") as f:
                total += next((int(line.split()[1]) * 1024 for line in f
                               if line.startswith("VmRSS:")), 0)
            for task in os.listdir(f"/proc/{p}/task"):
                with open(f"/proc/{p}/task/{task}/children") as f:
                    todo += [int(c) for c in f.read().split()]
        except (OSError, ValueError):  # the process ended meanwhile
            continue
    return total


def flexarm(args: list[str], env: dict) -> tuple[float, int, str, str]:
    """Wall time [s], peak memory of the process tree [bytes], stdout and stderr of one
    ``flexarm`` command in its own process."""
    t0 = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "flexarm.cli", *args], env=env, text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    peak = [0]
    running = threading.Event()
    running.set()

    def sample():
        while running.is_set():
            peak[0] = max(peak[0], _tree_rss(proc.pid))
            time.sleep(0.1)

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    out, err = proc.communicate()
    running.clear()
    sampler.join()
    if proc.returncode != 0:
        raise SystemExit(f"flexarm {' '.join(args)} failed ({proc.returncode}):\n{err}")
    return time.perf_counter() - t0, peak[0], out, err


def _row(what: str, dt: float, peak: int) -> str:
    return f"  {what:<34} {dt:7.1f} s  peak {peak / 2**20:7.0f} MB"


def run_robot(name: str, folder: Path, jobs: str | None, compare: bool) -> float:
    """Import, build and first CB modes of one robot in an empty cache; the total [s]."""
    urdf, options, pose = ROBOTS[name]
    env = dict(os.environ, FLEXARM_CACHE=str(folder / "cache"))
    env.setdefault("PYTHONPATH", str(Path(__file__).resolve().parents[1]))
    toml = str(folder / f"{name}.toml")
    print(f"{name}: {urdf.name} ({' '.join(options)}), empty cache")
    total = 0.0
    dt, peak, _, _ = flexarm(["import-urdf", str(urdf), *options, "-o", toml], env)
    total += dt
    print(_row("import-urdf", dt, peak))
    build = ["build", "--robot", toml] + (["-j", jobs] if jobs else [])
    dt, peak, out, _ = flexarm(build, env)
    total += dt
    print(_row(f"build (robot's mesh size{', -j ' + jobs if jobs else ''})", dt, peak))
    table = out.split("\n\n")[0]
    print("\n".join("    " + line for line in table.splitlines()))
    dt, peak, out, _ = flexarm(["modes", "--robot", toml, "--model", "cb", "--pose", pose,
                                "-n", "6"], env)
    total += dt
    print(_row(f"modes --model cb at {pose}", dt, peak))
    freqs = [line.split()[1] for line in out.splitlines() if line.strip()[:1].isdigit()]
    print(f"    first CB modes [Hz]: {', '.join(freqs[:6])}")
    verdict = "within" if total <= TARGET_S else "over"
    print(f"  URDF to first CB modes, cold:      {total:7.1f} s  ({verdict} the "
          f"{TARGET_S:.0f} s target)")
    if compare:
        dt, peak, out, _ = flexarm(["compare-models", "--robot", toml, "--poses", f"{P1};{P2}",
                                    "-o", str(folder / "compare")], env)
        print(_row("compare-models at P1 and P2 (full FE)", dt, peak))
        print("\n".join("    " + line for line in out.splitlines() if "wrote" not in line))
    return total


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--robots", default=",".join(ROBOTS),
                    help=f"comma-separated, of {', '.join(ROBOTS)}")
    ap.add_argument("--jobs", default=None, help="flexarm build -j (default: one per core)")
    ap.add_argument("--keep", default=None, help="folder to keep the robots and caches in")
    ap.add_argument("--compare", action="store_true",
                    help="also compare-models of the IRB 4600 with its full-FE reference")
    args = ap.parse_args()
    names = [n.strip() for n in args.robots.split(",") if n.strip()]
    unknown = [n for n in names if n not in ROBOTS]
    if unknown:
        ap.error(f"--robots: unknown {', '.join(unknown)} (known: {', '.join(ROBOTS)})")
    print(f"{time.strftime('%Y-%m-%d %H:%M')}, {os.cpu_count()} cores, load average at "
          f"start {os.getloadavg()[0]:.2f}")
    totals = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name in names:
            folder = Path(args.keep or tmp) / name
            folder.mkdir(parents=True, exist_ok=True)
            totals[name] = run_robot(name, folder, args.jobs,
                                     args.compare and name == "irb4600")
    print(f"load average at end {os.getloadavg()[0]:.2f}; cold URDF to first CB modes: "
          + ", ".join(f"{n} {t:.1f} s" for n, t in totals.items()))


if __name__ == "__main__":
    main()
