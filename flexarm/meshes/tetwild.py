"""Closed surface -> checked tetrahedral mesh with pytetwild (fTetWild), cached on disk.

pytetwild's output differs between identical calls and occasionally contains
slivers or flat elements, so every result is checked and a bad one is remeshed
(optimised, then with a slightly smaller edge length) instead of being patched.
"""

from __future__ import annotations

import contextlib
import logging
import os
import signal
import tempfile
import threading
import time
from collections.abc import Callable, Iterator

import numpy as np

from ..fe.errors import MeshError, MissingDependencyError
from ..fe.mesh import TetMesh
from ..fe.tolerances import tol as fe_tol
from .quality import dihedral_angles
from .tet_cache import cached_tetrahedralization
from .tolerances import tol

__all__ = ["tetrahedralize", "envelope", "MAX_TRIES", "RETRY_SHRINK"]

logger = logging.getLogger(__name__)

#: pytetwild runs per request before giving up.
MAX_TRIES = 3
#: Edge-length factor of the last try.
RETRY_SHRINK = 0.85

Progress = Callable[[str], None]


@contextlib.contextmanager
def _in_temp_dir() -> Iterator[str]:
    """Run the body inside a fresh temporary directory, restoring the cwd after.

    pytetwild writes ``__tracked_surface.stl`` into the current directory.  The
    working directory is process-wide: do not mesh from several threads at once.
    """
    previous = os.getcwd()
    with tempfile.TemporaryDirectory(prefix="flexarm-tetwild-") as folder:
        os.chdir(folder)
        try:
            yield folder
        finally:
            os.chdir(previous)


def _run_tetwild(
    vertices: np.ndarray, faces: np.ndarray, size: float, optimize: bool
) -> tuple[np.ndarray, np.ndarray]:
    """One pytetwild call: (n, 3) float64 points [m] and (m, 4) int tets (VTK order)."""
    try:
        import pytetwild
    except ImportError as exc:
        raise MissingDependencyError("pytetwild", "tetrahedralisation") from exc
    # The extension accepts only plain C-contiguous arrays (not trimesh's TrackedArray).
    v = np.array(vertices, dtype=np.float64, order="C")
    f = np.array(faces, dtype=np.int32, order="C")
    with _in_temp_dir(), _python_sigint():
        points, tets = pytetwild.tetrahedralize(
            v,
            f,
            edge_length_abs=float(size),
            optimize=bool(optimize),
            epsilon=envelope(float(np.linalg.norm(np.ptp(v, axis=0))), size),
            vtk_ordering=True,  # without it every element is negatively oriented
            quiet=True,
            num_threads=_threads(),
        )
    return np.asarray(points, dtype=np.float64), np.asarray(tets, dtype=np.int64)


def envelope(diagonal: float, size: float) -> float:
    """fTetWild's envelope over the bounding-box ``diagonal`` [m] for an edge of ``size``
    [m]: ``tol.tet_envelope``, or ``tol.tet_envelope_edge`` of the edge where larger.

    Examples
    --------
    >>> envelope(1.5, 0.03), round(envelope(0.18, 0.03), 5)  # a robot's arm, its wrist
    (0.001, 0.00556)
    """
    return max(tol.tet_envelope, tol.tet_envelope_edge * float(size) / float(diagonal))


def _threads() -> int:
    """fTetWild's threads: ``OMP_NUM_THREADS`` where set (a worker meshing beside others
    has 1: one process per core), else every core (0)."""
    try:
        return max(0, int(os.environ.get("OMP_NUM_THREADS", "0")))
    except ValueError:
        return 0


@contextlib.contextmanager
def _python_sigint() -> Iterator[None]:
    """Give Ctrl-C back to Python after the mesher.

    fTetWild's first call installs its own SIGINT handler, which ends the process at once
    and silently, and leaves it installed: every later Ctrl-C of the run (in a solve, in
    a file write) would kill the process without a message or the clean-up of temporary
    files.  During the call itself Ctrl-C still stops the process at once (the extension
    holds the GIL, so Python could not act on it before the mesh is done).
    """
    handler = signal.getsignal(signal.SIGINT)
    try:
        yield
    finally:
        if handler is not None and threading.current_thread() is threading.main_thread():
            signal.signal(signal.SIGINT, handler)


def _compact(points: np.ndarray, tets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Drop nodes no element uses; keep the order of the rest."""
    used = np.unique(tets)
    if len(used) == len(points):
        return points, tets
    new_id = np.full(len(points), -1, dtype=np.int64)
    new_id[used] = np.arange(len(used))
    return points[used], new_id[tets]


def _defect(points: np.ndarray, tets: np.ndarray) -> str | None:
    """Why a raw mesher result is unusable, or None if it is fine."""
    if len(tets) == 0:
        return "no tetrahedra"
    p = points[tets]
    d = p[:, 1:] - p[:, :1]
    vol = np.einsum("ij,ij->i", d[:, 0], np.cross(d[:, 1], d[:, 2])) / 6.0
    scale = np.abs(vol).mean()
    n_inverted = int((vol < -fe_tol.degenerate_volume * scale).sum())
    n_flat = int((np.abs(vol) <= fe_tol.degenerate_volume * scale).sum())
    n_slivers = int((dihedral_angles(points, tets).min(axis=1) < tol.sliver_dihedral_deg).sum())
    problems = []
    if n_inverted:
        problems.append(f"{n_inverted} inverted")
    if n_flat:
        problems.append(f"{n_flat} zero-volume")
    if n_slivers:
        problems.append(f"{n_slivers} sliver (dihedral < {tol.sliver_dihedral_deg:g} deg)")
    return ", ".join(problems) + " tetrahedra" if problems else None


def _attempts(size: float, optimize: bool) -> list[tuple[float, bool]]:
    """The (edge length, optimize) of each try: as asked, optimised, then finer."""
    return [(size, optimize), (size, True), (size * RETRY_SHRINK, True)][:MAX_TRIES]


def _mesh_checked(vertices, faces, size, optimize, name, progress: Progress) -> TetMesh:
    problems = []
    for i, (h, opt) in enumerate(_attempts(size, optimize), start=1):
        progress(f"{name}: tetrahedralizing, try {i}/{MAX_TRIES} (edge {h:.4g} m, optimize={opt})")
        start = time.perf_counter()
        try:
            points, tets = _run_tetwild(vertices, faces, h, opt)
        except MissingDependencyError:
            raise
        except Exception as exc:  # the C++ extension raises RuntimeError and others
            raise MeshError(f"{name}: pytetwild failed: {exc}") from exc
        points, tets = _compact(points, tets)
        problem = _defect(points, tets)
        elapsed = time.perf_counter() - start
        if problem is None:
            logger.info("%s: %d tetrahedra in %.1f s (try %d)", name, len(tets), elapsed, i)
            return TetMesh(points, tets)
        logger.warning("%s: try %d gave %s; meshing again", name, i, problem)
        problems.append(f"try {i}: {problem}")
    raise MeshError(
        f"{name}: no valid tetrahedral mesh after {MAX_TRIES} tries ({'; '.join(problems)})"
    )


def tetrahedralize(
    surface,
    size: float,
    optimize: bool = True,
    order: int = 1,
    cache: bool = True,
    name: str = "surface",
    progress: Progress | None = None,
) -> TetMesh:
    """Tetrahedral mesh of the solid inside a closed surface.

    Every result is checked (no inverted, zero-volume or sliver elements, see
    ``tol.sliver_dihedral_deg``); a bad one is remeshed up to ``MAX_TRIES`` times
    (optimised, then with the edge length times ``RETRY_SHRINK``).

    Parameters
    ----------
    surface : trimesh.Trimesh
        Closed, outward-wound surface [m] (e.g. from :func:`load_surface`).
    size : float
        Target edge length [m].
    optimize : bool
        Let fTetWild optimise element quality (slower; ``False`` often leaves
        flat elements, which then cost a second, optimised run).
    order : {1, 2}
        Tet4, or Tet10 with straight mid-edge nodes.
    cache : bool
        Reuse / store the result in the package cache (``tets``) (keyed by the surface's
        vertices and faces, ``size``, ``optimize``, ``order`` and the tolerances).
    name : str
        What to call the part in messages.
    progress : callable (str) -> None, optional
        Receives a few coarse progress messages.

    Returns
    -------
    TetMesh
        Positively oriented elements, no unused nodes.

    Raises
    ------
    MeshError
        No valid mesh after ``MAX_TRIES`` tries, or pytetwild failed.
    """
    def make(vertices, faces, report):
        logger.info("tetrahedralizing %s: %d faces, edge %.4g m", name, len(faces), size)
        return _mesh_checked(vertices, faces, float(size), optimize, name, report)

    return cached_tetrahedralization(surface, size, optimize, order, cache, name, progress, make)
