"""Jobs in worker processes: results in order, progress and warnings relayed, the first
failure raised, and Ctrl-C stops the workers with nothing half-written."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
import warnings
from pathlib import Path

import pytest

from flexarm.fe.files import atomic_path
from flexarm.fe.processes import can_spawn, default_jobs, run_jobs

pytestmark = pytest.mark.skipif(not can_spawn(), reason="no process semaphores here")

ROOT = Path(__file__).resolve().parents[2]


def square(x: int, progress=None) -> tuple[int, int]:
    """x squared and the worker's process id; says one line and warns once."""
    progress(f"squaring {x}")
    warnings.warn(f"{x} is a number", UserWarning, stacklevel=1)
    return x * x, os.getpid()


def fails_on_two(x: int, progress=None) -> int:
    if x == 2:
        raise ValueError("links.two: no mesh")
    return x


def writes_forever(path: str, progress=None) -> None:
    """Start writing ``path`` through a temporary file, say so, and never finish."""
    with atomic_path(Path(path)) as tmp:
        tmp.write_text("half")
        progress(f"writing {Path(path).name} in {os.getpid()}")
        while True:  # until the parent stops this worker
            time.sleep(0.05)


def test_default_jobs_is_the_cores_here():
    assert 1 <= default_jobs() <= (os.cpu_count() or 1)


def test_results_in_order_progress_and_warnings_relayed():
    said = []
    with pytest.warns(UserWarning) as caught:
        results = run_jobs(square, [(1,), (2,), (3,)], jobs=2, progress=said.append)
    assert [r for r, _ in results] == [1, 4, 9]
    assert {pid for _, pid in results} != {os.getpid()}  # computed in workers
    assert sorted(said) == ["squaring 1", "squaring 2", "squaring 3"]
    assert sorted(str(w.message) for w in caught) == ["1 is a number", "2 is a number",
                                                      "3 is a number"]


def test_one_job_runs_here():
    with pytest.warns(UserWarning, match="4 is a number"):
        results = run_jobs(square, [(4,)], jobs=2, progress=lambda s: None)
    assert results[0] == (16, os.getpid())
    with pytest.raises(ValueError, match="jobs must be at least 1"):
        run_jobs(square, [(1,), (2,)], jobs=0)


def test_the_first_failure_is_raised():
    with pytest.raises(ValueError, match="links.two: no mesh"):
        run_jobs(fails_on_two, [(1,), (2,), (3,)], jobs=2)


def test_ctrl_c_stops_the_workers_and_leaves_nothing_half_written(tmp_path):
    """Waits for both workers to be inside their writes (a state, not a time), then
    interrupts the parent as Ctrl-C would."""
    script = (
        "import signal, sys\n"
        # a process started in the background inherits SIGINT ignored: Ctrl-C as a terminal
        # gives it
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        "from flexarm.fe.processes import run_jobs\n"
        "from tests.fe.test_processes import writes_forever\n"
        "try:\n"
        f"    run_jobs(writes_forever, [(r'{tmp_path / 'a.txt'}',), (r'{tmp_path / 'b.txt'}',)],"
        " jobs=2, progress=lambda s: print(s, flush=True))\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted', flush=True)\n"
        "    sys.exit(130)\n")
    parent = subprocess.Popen([sys.executable, "-c", script], cwd=ROOT, text=True,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    workers = []
    while len(workers) < 2:
        line = parent.stdout.readline()
        assert line, parent.stderr.read()
        workers.append(int(line.split()[-1]))
    parent.send_signal(signal.SIGINT)
    rest, err = parent.communicate(timeout=120)
    assert parent.returncode == 130 and rest.strip() == "interrupted", err
    for pid in workers:  # stopped, not left running
        with pytest.raises(ProcessLookupError):
            os.kill(pid, 0)
    # no output file at all: only the temporary files of the two writes
    assert not (tmp_path / "a.txt").exists() and not (tmp_path / "b.txt").exists()
    assert all(p.name.startswith(".") and ".part" in p.name for p in tmp_path.iterdir())
