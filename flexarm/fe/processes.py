"""Independent jobs in worker processes, one per core, and their progress in this process.

Meshing a robot is a set of independent, CPU-bound jobs (one per link) in libraries that
hold the GIL or a process-wide state (Gmsh, fTetWild): processes, not threads, run them
side by side.  Workers are *spawned* (this process may hold BLAS or OpenMP threads that a
fork would copy), each with one BLAS and one OpenMP thread, so ``jobs`` workers keep
``jobs`` cores busy.  What a worker says (progress lines, log warnings, Python warnings)
reaches this process's ``progress``, logging and warnings as if the job ran here.

Ctrl-C is this process's to handle: workers ignore it; on an interrupt, or on the first
job that fails, the jobs not started are cancelled and the workers stopped.

:func:`run_child` runs one call in a child process of its own with a CPU-time limit: a
native library that may never return (Gmsh on some surfaces) is stopped by the kernel when
its budget is spent, and the caller tries something else.  The child follows its parent:
it ignores Ctrl-C, and ends when the process that started it is gone (a stopped worker
leaves no meshing grandchild behind).  A stopped
worker leaves no half-written file behind where the package writes through
:func:`~flexarm.fe.files.atomic_path` (only a temporary ``.part`` file, which the cache
sweeps away later).
"""

from __future__ import annotations

import logging
import math
import os
import signal
import threading
import time
import warnings
from collections.abc import Callable, Sequence
from typing import Any

__all__ = ["default_jobs", "can_spawn", "run_jobs", "run_child", "ChildTimeout"]

log = logging.getLogger(__name__)

Progress = Callable[[str], None]

#: Environment a worker runs with: one thread per native library.
_WORKER_ENV = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}

#: The queue of this worker process (set by :func:`_init_worker`).
_queue = None


def default_jobs() -> int:
    """Worker processes for "one per core": the cores this process may run on.

    Examples
    --------
    >>> default_jobs() >= 1
    True
    """
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


def can_spawn() -> bool:
    """True when this platform gives multiprocessing its locks (some containers have no
    ``/dev/shm``, and every queue needs a semaphore)."""
    import multiprocessing

    try:
        multiprocessing.get_context("spawn").SimpleQueue()
    except (OSError, ImportError):
        return False
    return True


class _QueueLog(logging.Handler):
    """Send a worker's warnings and errors to the parent as ``("log", name, level, text)``."""

    def emit(self, record: logging.LogRecord) -> None:
        try:
            _queue.put(("log", record.name, record.levelno, record.getMessage()))
        except Exception:  # noqa: BLE001 - a log line must never fail the job
            self.handleError(record)


def _init_worker(queue) -> None:
    global _queue
    _queue = queue
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    os.environ.update(_WORKER_ENV)
    try:
        from threadpoolctl import threadpool_limits

        threadpool_limits(1)
    except ImportError:  # pragma: no cover - threadpoolctl is a declared dependency
        pass
    root = logging.getLogger()
    root.handlers[:] = [_QueueLog(logging.WARNING)]
    root.setLevel(logging.WARNING)


def _job(function: Callable, args: tuple, kwargs: dict) -> tuple[Any, list]:
    """``function(*args, progress=..., **kwargs)`` in a worker; its result and warnings."""
    def say(text: str) -> None:
        _queue.put(("say", text))

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = function(*args, progress=say, **kwargs)
    return result, [(w.category, str(w.message)) for w in caught]


def _relay(queue, progress: Progress | None, done: threading.Event) -> None:
    """Pass on what the workers say until ``done`` is set and nothing is left.

    The parent never writes to the queue: a worker stopped while it was writing may hold
    the queue's lock for ever."""
    while not (done.is_set() and queue.empty()):
        if queue.empty():
            done.wait(0.05)
            continue
        item = queue.get()
        if item[0] == "say":
            if progress is not None:
                progress(item[1])
        else:
            logging.getLogger(item[1]).log(item[2], item[3])


def _started_relay(ctx, progress: Progress | None):
    """A queue for worker processes, and the running thread that relays it here until the
    returned event is set: (queue, event, thread)."""
    queue = ctx.SimpleQueue()
    finished = threading.Event()
    relay = threading.Thread(target=_relay, args=(queue, progress, finished), daemon=True,
                             name="flexarm-worker-progress")
    relay.start()
    return queue, finished, relay


def _stop(pool) -> None:
    """Cancel what has not started and stop the workers now."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        if process.is_alive():
            process.terminate()
    for process in processes:
        process.join()


def run_jobs(function: Callable, calls: Sequence[tuple], jobs: int | None = None,
             progress: Progress | None = None, **kwargs) -> list:
    """``function(*args, progress=progress, **kwargs)`` for every ``args`` in ``calls``, in
    up to ``jobs`` worker processes; the results in the order of ``calls``.

    Parameters
    ----------
    function : callable
        A module-level function (workers import it by name) taking ``progress=``.
    calls : sequence of tuple
        Positional arguments of each call (picklable).
    jobs : int, optional
        Worker processes (default :func:`default_jobs`).  With 1 job, one call or no
        process semaphores the calls run here, in order.
    progress : callable (str) -> None, optional
        Receives every progress line of every job, as it is said.

    Raises
    ------
    Exception
        The first job's exception that failed (the other jobs are stopped).
    KeyboardInterrupt
        Ctrl-C in this process (the workers are stopped).

    Examples
    --------
    >>> run_jobs(divmod, [], jobs=1)
    []
    """
    import multiprocessing
    from concurrent.futures import FIRST_EXCEPTION, ProcessPoolExecutor, wait
    from concurrent.futures.process import BrokenProcessPool

    from .errors import FlexarmError

    jobs = default_jobs() if jobs is None else int(jobs)
    if jobs < 1:
        raise ValueError(f"jobs must be at least 1, got {jobs}")
    if jobs == 1 or len(calls) <= 1 or not can_spawn():
        return [function(*args, progress=progress, **kwargs) for args in calls]
    ctx = multiprocessing.get_context("spawn")
    queue, finished, relay = _started_relay(ctx, progress)
    pool = ProcessPoolExecutor(min(jobs, len(calls)), mp_context=ctx,
                               initializer=_init_worker, initargs=(queue,))
    log.info("%d jobs in %d worker processes", len(calls), min(jobs, len(calls)))
    try:
        futures = [pool.submit(_job, function, tuple(args), kwargs) for args in calls]
        done, _ = wait(futures, return_when=FIRST_EXCEPTION)
        failed = next((f for f in futures if f in done and f.exception() is not None), None)
        if failed is not None:
            raise failed.exception()
        outcomes = [f.result() for f in futures]
        pool.shutdown(wait=True)
    except BrokenProcessPool as exc:
        _stop(pool)
        raise FlexarmError(f"a worker process ended abruptly (killed, or out of memory?): "
                           f"run with one job to see where ({exc})") from exc
    except BaseException:
        _stop(pool)
        raise
    finally:
        finished.set()
        relay.join()
    for _, caught in outcomes:
        for category, message in caught:
            warnings.warn(message, category, stacklevel=2)
    return [result for result, _ in outcomes]


# ----------------------------------------------------------------- one call, time-limited
class ChildTimeout(Exception):
    """A :func:`run_child` call spent its CPU-time budget (the child was stopped)."""


#: How often a child checks that its parent is still there, and the parent that its child
#: is still running [s].
_POLL = 0.1


def _orphan_watch(parent: int) -> None:
    """End this child as soon as its parent is gone (killed, or stopped as a worker)."""
    while os.getppid() == parent:
        time.sleep(_POLL)
    os._exit(1)


def _child(conn, queue, parent: int, cpu_seconds: float | None, function: Callable,
           args: tuple, kwargs: dict) -> None:
    """The child's side of :func:`run_child`: limits, the call, its outcome to ``conn``."""
    _init_worker(queue)
    threading.Thread(target=_orphan_watch, args=(parent,), daemon=True).start()
    if cpu_seconds is not None:
        import resource

        # counted from here (the imports before are not the call's); the kernel sends
        # SIGXCPU, whose default action ends the process, at the soft limit
        used = sum(resource.getrusage(resource.RUSAGE_SELF)[:2])
        soft = math.ceil(used + cpu_seconds)
        resource.setrlimit(resource.RLIMIT_CPU, (soft, soft + 5))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            outcome = ("ok", function(*args, **kwargs))
        except Exception as exc:  # noqa: BLE001 - handed to the parent to raise
            outcome = ("error", exc)
    found = [(w.category, str(w.message)) for w in caught]
    try:
        conn.send((*outcome, found))
    except Exception as exc:  # noqa: BLE001 - an exception that does not pickle
        conn.send(("error", RuntimeError(f"{type(outcome[1]).__name__}: {outcome[1]} "
                                         f"({exc})"), found))
    conn.close()


def run_child(function: Callable, args: tuple = (), kwargs: dict | None = None,
              cpu_seconds: float | None = None, name: str = "child") -> Any:
    """``function(*args, **kwargs)`` in a child process, stopped after ``cpu_seconds``.

    The child is *spawned* with one BLAS and one OpenMP thread; its warnings and log
    warnings reach this process as if the call ran here.

    Parameters
    ----------
    function : callable
        A module-level function (the child imports it by name); arguments and result
        must pickle.
    args, kwargs
        Its arguments.
    cpu_seconds : float, optional
        CPU time [s] the call may take (the child's imports not counted; whole seconds,
        rounded up); None: no limit.  POSIX only (elsewhere no limit is set); where
        processes cannot be spawned (:func:`can_spawn`) the call runs here, unlimited.
    name : str
        What to call the call in messages.

    Returns
    -------
    object
        What ``function`` returned.

    Raises
    ------
    ChildTimeout
        The budget was spent; the child is stopped.
    Exception
        What ``function`` raised in the child (re-raised here).
    FlexarmError
        The child ended without an answer (killed, out of memory, a crash in native code).
    KeyboardInterrupt
        Ctrl-C here (the child is stopped first).

    Examples
    --------
    >>> run_child(divmod, (7, 2), cpu_seconds=60)
    (3, 1)
    """
    import multiprocessing

    from .errors import FlexarmError

    if not can_spawn():  # no process semaphores: here, without a limit
        log.info("%s: run in this process, without a time limit (no process semaphores)", name)
        return function(*args, **(kwargs or {}))
    try:
        import resource  # noqa: F401 - RLIMIT_CPU in the child
    except ImportError:  # pragma: no cover - not POSIX
        cpu_seconds = None
    ctx = multiprocessing.get_context("spawn")
    queue, finished, relay = _started_relay(ctx, None)
    receive, send = ctx.Pipe(duplex=False)
    child = ctx.Process(target=_child, name=f"flexarm-{name}", daemon=False,
                        args=(send, queue, os.getpid(), cpu_seconds, function, tuple(args),
                              dict(kwargs or {})))
    answer = None
    try:
        child.start()
        send.close()  # the child's end: EOF here once the child is gone
        while answer is None and (child.is_alive() or receive.poll()):
            if receive.poll(_POLL):
                try:
                    answer = receive.recv()
                except EOFError:
                    break
        child.join()
    except BaseException:
        if child.is_alive():
            child.terminate()
        child.join()
        raise
    finally:
        finished.set()
        relay.join()
        receive.close()
    if answer is None:
        if child.exitcode == -getattr(signal, "SIGXCPU", 0):
            raise ChildTimeout(f"{name}: stopped after {cpu_seconds:g} CPU-s")
        raise FlexarmError(f"{name}: the child process ended without an answer (exit code "
                           f"{child.exitcode}: killed, out of memory, or a crash)")
    kind, value, caught = answer
    for category, message in caught:
        warnings.warn(message, category, stacklevel=2)
    if kind == "error":
        raise value
    return value
