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


# --- one call in a child process, with a CPU-time limit -------------------------------
def spins(seconds: float, progress=None) -> int:
    """Busy for ``seconds`` of CPU time, then the child's process id; warns once."""
    start = time.process_time()
    while time.process_time() - start < seconds:
        pass
    warnings.warn("spun", UserWarning, stacklevel=1)
    return os.getpid()


def spins_in_a_child(path: str, progress=None) -> None:
    """Say the child's id (in ``path``), then run a child that never ends."""
    from flexarm.fe.processes import run_child

    run_child(_spins_and_tells, (path,), cpu_seconds=3600)


def _spins_and_tells(path: str) -> None:
    Path(path).write_text(str(os.getpid()))
    spins(3600)


def test_a_child_answers_and_its_warnings_and_errors_come_here():
    from flexarm.fe.processes import run_child

    with pytest.warns(UserWarning, match="spun"):
        pid = run_child(spins, (0.01,), cpu_seconds=60)
    assert pid != os.getpid()
    with pytest.raises(ValueError, match="links.two: no mesh"):
        run_child(fails_on_two, (2,))


def test_a_child_over_its_cpu_budget_is_stopped():
    """One CPU-s of budget against an hour of work: stopped by the kernel (SIGXCPU)."""
    from flexarm.fe.processes import ChildTimeout, run_child

    with pytest.raises(ChildTimeout, match=r"^spin: stopped after 1 CPU-s$"):
        run_child(spins, (3600,), cpu_seconds=1, name="spin")


def _wait_for_pid(path: Path, parent: subprocess.Popen) -> int:
    while not path.exists() or not path.read_text():  # a state, not a time
        assert parent.poll() is None, parent.stderr.read()
        time.sleep(0.05)
    return int(path.read_text())


def _is_gone(pid: int) -> bool:
    """True once ``pid`` has ended (a zombie of a living parent counts as ended)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().split(")")[-1].split()[0] == "Z"
    except FileNotFoundError:
        return True


@pytest.mark.parametrize("how", ["ctrl-c", "worker stopped"])
def test_the_child_ends_with_its_caller(tmp_path, how):
    """Ctrl-C in the caller stops the child before the KeyboardInterrupt goes on; a caller
    that is itself a stopped pool worker leaves no child behind."""
    tell = tmp_path / "child.pid"
    if how == "ctrl-c":
        call = (f"run_child(_spins_and_tells, (r'{tell}',), cpu_seconds=3600)")
    else:
        call = (f"run_jobs(spins_in_a_child, [(r'{tell}',), (r'{tmp_path / 'b'}',)], jobs=2)")
    script = (
        "import signal, sys\n"
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        "from flexarm.fe.processes import run_child, run_jobs\n"
        "from tests.fe.test_processes import _spins_and_tells, spins_in_a_child\n"
        "try:\n"
        f"    {call}\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted', flush=True)\n"
        "    sys.exit(130)\n")
    parent = subprocess.Popen([sys.executable, "-c", script], cwd=ROOT, text=True,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    child = _wait_for_pid(tell, parent)
    parent.send_signal(signal.SIGINT)
    out, err = parent.communicate(timeout=120)
    assert parent.returncode == 130 and out.strip() == "interrupted", err
    deadline = time.monotonic() + 120
    while not _is_gone(child) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert _is_gone(child)
