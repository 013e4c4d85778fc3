"""The main job on built-in data: ``flexarm demo``.

Each step (:mod:`~flexarm.studies.demo_part`, :mod:`~flexarm.studies.demo_models`,
:mod:`~flexarm.studies.demo_measurements`) writes its tables and pictures into one
output folder and returns a frozen :class:`~flexarm.studies.demo_results.StepResult`
with the lines it adds to ``index.md``; a step whose optional part (e.g. off-screen
rendering) is unavailable says so in the index instead of failing the whole demo.
Expensive results come from the on-disk cache, so a warm run is quick: superelements,
pictures and the demo's own results (diagnosis, maps, accuracy study:
:mod:`~flexarm.studies.demo_cache`).  This module runs the steps, in order or two
processes wide.
"""

from __future__ import annotations

import logging
import os
import sys
import time
from pathlib import Path

from ..fe.files import atomic_folder
from .demo_cache import is_warm, mark_warm
from .demo_measurements import measurement_step
from .demo_models import emodel_step, flexible_arm_step, flexible_step
from .demo_part import part_step
from .demo_results import DemoResult, Progress, StepResult
from .demo_study import accuracy_study, study_references, study_variants

__all__ = ["DemoResult", "run_demo"]

log = logging.getLogger(__name__)


def run_demo(folder="flexarm-demo", progress: Progress | None = None, size: float = 0.03,
             part: bool = False, jobs: int = 2) -> DemoResult:
    """Run every demo step into ``folder`` and write its ``index.md``.

    Parameters
    ----------
    folder : path-like
        Output folder (created).  Everything is written into a temporary sibling folder
        and moved in when the run is complete (:func:`~flexarm.fe.files.
        atomic_folder`); other files already in ``folder`` are kept.
    progress : callable, optional
        Receives one line per step (from a helper thread while a worker runs).
    size : float
        Edge length of the part-level mesh [m].
    part : bool
        Also run the single-part pipeline (full FE modes of one cast link).
    jobs : int
        Processes to use: with 2 or more, a second process computes the accuracy
        study's full-FE references (most of a cold run) into the cache, then runs the
        E-model step, while the other steps run here, and the off-screen render probe
        starts at once in the background.  The second process is forked where that is
        safe (Linux, no other thread running, BLAS threads on pthreads), after the
        modules both need are loaded here once; else spawned.  ``1`` runs everything in
        order in this process, and so does a warm run (an earlier run of this package
        with the same options completed, so every step is mostly cache reads and
        starting a second process costs more than it saves).  The index is the same
        either way.

    Returns
    -------
    DemoResult
        Folder, index lines, headline figures and wall time [s].
    """
    progress = progress or log.info
    out = Path(folder)
    t0 = time.perf_counter()
    if jobs > 1 and not _can_spawn():
        progress("demo: no process semaphores here (/dev/shm?), running the steps in order")
        jobs = 1
    if jobs > 1 and is_warm(size, part):
        jobs = 1
    run = _run_in_order if jobs <= 1 else _run_parallel
    # built aside and moved in when complete, index.md last: an interrupted run leaves
    # the folder as it was
    with atomic_folder(out, last="index.md") as tmp:
        steps = run(tmp, progress, size, part)
        result = DemoResult.of(out, steps, time.perf_counter() - t0)
        (tmp / "index.md").write_text(result.index_text())
    mark_warm(size, part)
    return result


def _run_in_order(out: Path, progress: Progress, size: float,
                  part: bool) -> list[StepResult]:
    """Every step in this process, in index order."""
    first = [part_step(out, progress, size)] if part else []
    return [*first, emodel_step(out, progress), flexible_step(out, progress),
            measurement_step(out, progress)]


def _can_spawn() -> bool:
    """True when this platform gives multiprocessing its locks (some containers have
    no /dev/shm, and every queue needs a semaphore)."""
    import multiprocessing

    try:
        multiprocessing.get_context("spawn").SimpleQueue()
    except (OSError, ImportError):
        return False
    return True


def _run_parallel(out: Path, progress: Progress, size: float,
                  part: bool) -> list[StepResult]:
    """The accuracy study's full-FE references, then the E-model step, in a second
    process; the other steps and the study's variants here (same index).

    The references (the Tet10 one above all) are most of a cold run, and the E-model
    step makes the two processes' shares about even.  The study is then read back from
    what both processes computed into the cache (:mod:`~flexarm.studies.demo_study`).
    """
    import multiprocessing
    import threading
    from concurrent.futures import ProcessPoolExecutor

    from ..reduction.render import prefetch_render_backend

    ctx = multiprocessing.get_context("fork" if _ready_to_fork() else "spawn")
    queue = ctx.SimpleQueue()
    relay_thread = threading.Thread(target=_relay, args=(queue, progress),
                                    name="flexarm-demo-progress", daemon=True)
    try:
        with ProcessPoolExecutor(1, mp_context=ctx, initializer=_init_worker,
                                 initargs=(queue,)) as pool:
            # The worker starts first (a fork copies this process, so no thread of ours
            # may run yet): its start overlaps the work here.  Both processes read the
            # same tetrahedra: the demo arm ships its link meshes (pinned volume meshes).
            references = pool.submit(_worker_job, str(out), "references")
            emodel_job = pool.submit(_worker_job, str(out), "emodel")
            relay_thread.start()
            prefetch_render_backend()
            first = [part_step(out, progress, size)] if part else []
            flexible = flexible_arm_step(out, progress)
            measurements = measurement_step(out, progress)
            progress("arm: accuracy study at P1: variants here, full-FE references in the "
                     "second process (cached after the first run)")
            study_variants(progress)
            references.result()
            # every part of it is in the cache now: its progress lines would repeat
            study = accuracy_study(out, log.info)
            emodel = emodel_job.result()
    finally:
        queue.put(None)
        if relay_thread.is_alive():
            relay_thread.join()
    return [*first, emodel, flexible.with_study(study), measurements]


def _ready_to_fork() -> bool:
    """Whether the worker may be forked from here, with what both processes need loaded
    here first (:func:`_load_shared`) when it may.

    A forked worker starts with this process's modules loaded instead of importing them
    again, which is most of a warm run.  It may be forked on Linux when no other thread
    runs here (a fork copies the locks other threads hold, not the threads) and every
    BLAS library loaded here runs its threads on plain pthreads (OpenBLAS restarts them
    in the child; an OpenMP runtime that has run in the parent may hang there), checked
    after the shared modules are loaded.  Else it is spawned.
    """
    import threading

    if sys.platform != "linux" or threading.active_count() != 1:
        return False
    _load_shared()
    from threadpoolctl import threadpool_info

    return all(pool.get("threading_layer") == "pthreads" for pool in threadpool_info())


def _load_shared() -> None:
    """Before a fork: load once what both processes need (the robot description and the
    mesh libraries its checks import, matplotlib, the validation layer, the full-FE
    models, the package digest the demo's cache keys use)."""
    from .. import validation  # noqa: F401 - loaded for both processes
    from ..assembly import full_fe  # noqa: F401 - loaded for both processes
    from ..fe.cache import package_digest
    from ..fe.plotting import pyplot
    from ..robot import load_robot

    load_robot()
    pyplot()
    package_digest()


def _relay(queue, progress: Progress) -> None:
    """Hand the worker's progress lines to ``progress`` until a None arrives."""
    while (line := queue.get()) is not None:
        progress(line)


#: Progress channel of a worker process (set by :func:`_init_worker`).
_worker_say: Progress | None = None


def _init_worker(queue) -> None:
    """Send the worker's progress lines to the parent through ``queue``."""
    global _worker_say
    _worker_say = queue.put


def _worker_job(folder: str, name: str) -> StepResult | None:
    """Job ``name`` (a key of ``_WORKER_JOBS``) on the output folder ``folder`` in a worker
    process, with one BLAS thread.

    Progress lines go to the parent through the queue given to :func:`_init_worker`.
    """
    from threadpoolctl import threadpool_limits

    say = _worker_say or (lambda s: None)
    # The parent keeps the other core busy; two BLAS pools of two threads would fight.
    # MKL (PARDISO) is loaded later, by the job: it reads its thread count then.
    os.environ.update({"MKL_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"})
    with threadpool_limits(1):
        return _WORKER_JOBS[name](Path(folder), say)


def _references(out: Path, progress: Progress) -> None:
    """The accuracy study's full-FE references into the cache (nothing written to ``out``)."""
    study_references(progress)


#: What a worker process runs while this one runs the other steps: (output folder,
#: progress) -> the step's result, or None for work that only fills the cache.
_WORKER_JOBS = {"references": _references, "emodel": emodel_step}
