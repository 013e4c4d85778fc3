"""Pictures of superelement results with PyVista: PNG, animated GIF, or a window.

Off-screen rendering needs a system GL library; without one VTK *crashes the process*
instead of raising.  :func:`render_backend` therefore first tries a tiny render in a
subprocess (EGL, then OSMesa, then VTK's default window) and raises a clear
:class:`FlexarmError` when none works.  pyvista and imageio are imported only here.
"""

from __future__ import annotations

import functools
import logging
import os
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np

from ..fe.errors import FlexarmError, require
from ..fe.picture_cache import cached_picture
from .mode_file import MODE_EXTENSIONS, write_mode_mesh
from .recovery import mode_coordinates, mode_shape
from .superelement import Superelement
from .tolerances import tol

__all__ = ["render_backend", "prefetch_render_backend", "has_display", "render_field",
           "render_mode", "write_mode", "MODE_EXTENSIONS", "scene_key", "probe_key"]

log = logging.getLogger(__name__)

_WINDOWS = ("vtkEGLRenderWindow", "vtkOSOpenGLRenderWindow", "")
_PROBE = ("import pyvista as pv; p = pv.Plotter(off_screen=True, window_size=(64, 64)); "
          "p.add_mesh(pv.Sphere()); p.screenshot(return_img=True); p.close()")


def has_display() -> bool:
    """True when an interactive window can be opened (X11/Wayland, or macOS/Windows)."""
    if sys.platform in ("darwin", "win32"):
        return True
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


# One probe at a time: a prefetch thread and the first picture must not both probe.
_probe_lock = threading.Lock()


#: Environment variables that decide which off-screen window works (with the versions of
#: Python, PyVista and VTK and the machine they make the probe's cache key).
_PROBE_ENV = ("DISPLAY", "WAYLAND_DISPLAY", "VTK_DEFAULT_OPENGL_WINDOW", "PYVISTA_OFF_SCREEN",
              "LIBGL_ALWAYS_SOFTWARE", "MESA_GL_VERSION_OVERRIDE", "LD_LIBRARY_PATH")


def probe_key() -> str:
    """Cache key of this machine's probe result: the probe itself, host, interpreter,
    PyVista and VTK versions and the display/GL environment variables
    (:data:`_PROBE_ENV`)."""
    import platform

    from ..fe.cache import cache_key

    return cache_key("render-probe", _PROBE, _WINDOWS, platform.node(), sys.executable,
                     sys.version, tuple((k, os.environ.get(k)) for k in _PROBE_ENV),
                     libraries=("pyvista", "vtk", "imageio"))


@functools.lru_cache(maxsize=1)
def _probed_backend() -> str:
    from ..fe.cache import cached

    for mod in ("pyvista", "imageio"):
        require(mod, "pictures")
    # a subprocess render costs ~2 s; only a working answer is stored (a failure raises)
    window = cached("render-probe", probe_key(), _probe_windows).value
    os.environ["VTK_DEFAULT_OPENGL_WINDOW"] = window
    return window


def _probe_windows() -> str:
    """The first window class that renders a sphere off-screen in a subprocess."""
    user = os.environ.get("VTK_DEFAULT_OPENGL_WINDOW")
    tried = []
    for window in ((user,) if user else ()) + _WINDOWS:
        env = dict(os.environ, VTK_DEFAULT_OPENGL_WINDOW=window)
        try:
            ok = subprocess.run([sys.executable, "-c", _PROBE], env=env, capture_output=True,
                                timeout=tol.render_probe_seconds).returncode == 0
        except subprocess.TimeoutExpired:
            ok = False
        tried.append(window or "default")
        if ok:
            os.environ["VTK_DEFAULT_OPENGL_WINDOW"] = window
            log.info("off-screen rendering with %s", window or "VTK's default window")
            return window
    raise FlexarmError(
        "cannot render off-screen (tried " + ", ".join(tried) + "): install a GL library, "
        "e.g. 'apt-get install libegl1 libgl1-mesa-dri' or 'apt-get install libosmesa6'"
    )


def render_backend() -> str:
    """The VTK render window class that renders off-screen here ("" = VTK's default).

    Sets ``VTK_DEFAULT_OPENGL_WINDOW`` for this process.  A user setting is probed
    first and kept if it works.  The answer is cached for the process
    (``render_backend.cache_clear()`` forgets it) and, per machine, in the on-disk
    cache (kind ``render-probe``, keyed by :func:`probe_key`): delete that entry after
    installing or removing a GL library.
    """
    with _probe_lock:
        return _probed_backend()


render_backend.cache_clear = _probed_backend.cache_clear


def prefetch_render_backend() -> None:
    """Start :func:`render_backend`'s probe in a background thread and return at once.

    The probe is a subprocess that imports PyVista and renders a sphere (~2 s); a job
    that draws pictures late (``flexarm demo``) starts it early so nobody waits for
    it.  Errors are not raised here: the first picture raises them.
    """
    def probe():
        try:
            render_backend()
        except Exception:  # noqa: BLE001 - reported by the first real render_backend() call
            pass

    threading.Thread(target=probe, name="flexarm-render-probe", daemon=True).start()


def _require_surface(se: Superelement) -> None:
    if se.surface_points is None or se.T is None:
        raise FlexarmError("this superelement has no surface mesh or recovery matrix "
                           "(read it from HDF5 or NPZ, not from DMIG or Matrix Market)")


def _surface(se: Superelement):
    _require_surface(se)
    import pyvista as pv

    faces = np.column_stack([np.full(len(se.surface_faces), 3), se.surface_faces]).ravel()
    return pv.PolyData(np.asarray(se.surface_points, dtype=float), faces)


def _picture_suffix(path, interactive: bool) -> str:
    """Check a picture target and return its suffix (``""`` without a file).

    A file must be ``.png`` or ``.gif`` (then the off-screen backend is chosen);
    ``interactive`` needs a display; one of the two must be asked for.
    """
    if interactive and not has_display():
        raise FlexarmError("--interactive needs a display (DISPLAY or WAYLAND_DISPLAY is unset)")
    if path is None and not interactive:
        raise ValueError("give an output path (.png or .gif) or interactive=True")
    suffix = Path(path).suffix.lower() if path is not None else ""
    if path is not None and suffix not in (".png", ".gif"):
        raise ValueError(f"picture must be .png or .gif, got '{path}'")
    if path is not None:
        render_backend()
    return suffix


@functools.cache
def _code_digest(*files: str) -> str:
    from ..fe.files import file_digest

    return "".join(file_digest(f) for f in (__file__, *files))


def scene_key(path, *parts, code: tuple[str, ...] = ()) -> str:
    """Picture-cache key of a PyVista scene written to ``path`` (its suffix counts):
    ``parts`` is everything drawn (arrays by content), ``code`` the source files that
    draw it (this module always: any edit of the drawing code redraws), plus the render
    window class and the PyVista, VTK and imageio versions."""
    from ..fe.picture_cache import picture_key

    return picture_key("pyvista", Path(path).suffix.lower(), render_backend(),
                       _code_digest(*code), *parts, libraries=("pyvista", "vtk", "imageio"))


def save_picture(plotter, path, n_frames: int, move) -> Path:
    """Write ``plotter`` to ``path``: a ``.png`` still, or a ``.gif`` of one oscillation.

    ``move(phase)`` sets the deformed meshes for ``phase`` in [-1, 1] (one call per frame).
    The plotter is closed afterwards.
    """
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    if out.suffix.lower() == ".png":
        plotter.screenshot(str(out))
    else:
        plotter.open_gif(str(out))
        for phase in np.sin(2 * np.pi * np.arange(n_frames) / n_frames):
            move(phase)
            plotter.write_frame()
    plotter.close()
    return out


def render_field(se: Superelement, u: np.ndarray, path=None, title: str = "",
                 amplitude: float = 0.1, n_frames: int = 24, interactive: bool = False,
                 window_size=(1024, 768)) -> Path | None:
    """Draw the surface deformed by ``u`` (n_nodes, 3) [m], coloured by ``|u|``.

    Parameters
    ----------
    path : str or Path, optional
        ``.png`` (still) or ``.gif`` (``n_frames`` of a harmonic oscillation).
    amplitude : float
        Largest drawn displacement as a fraction of the bounding-box diagonal.
    interactive : bool
        Also open a window (only when :func:`has_display`).
    """
    _picture_suffix(path, interactive)
    _require_surface(se)
    us = np.asarray(u, dtype=float)[se.surface_nodes]
    out = None
    if path is not None:
        key = scene_key(path, "field", np.asarray(se.surface_points, dtype=float),
                        np.asarray(se.surface_faces), us, title, amplitude, n_frames,
                        tuple(window_size))
        out = cached_picture(path, key, lambda target: _draw_field(
            se, us, target, title, amplitude, n_frames, window_size))[0]
    if interactive:
        import pyvista as pv

        surf = _surface(se)
        base, scale = surf.points.copy(), _field_scale(surf, us, amplitude)
        moved = surf.copy()
        moved["|u|"] = np.linalg.norm(us, axis=1)
        moved.points = base + scale * us
        q = pv.Plotter()
        q.add_mesh(surf, style="wireframe", color="grey", opacity=0.35)
        q.add_mesh(moved, scalars="|u|", cmap="viridis")
        q.add_title(title, font_size=12)
        q.show()
    return out


def _field_scale(surf, us: np.ndarray, amplitude: float) -> float:
    """Drawing scale of ``us``: its largest is ``amplitude`` of the bounding diagonal."""
    diag = float(np.linalg.norm(np.ptp(surf.points, axis=0)))
    return amplitude * diag / max(float(np.linalg.norm(us, axis=1).max()), np.finfo(float).tiny)


def _draw_field(se: Superelement, us: np.ndarray, path, title: str, amplitude: float,
                n_frames: int, window_size) -> Path:
    """Draw the surface of ``se`` deformed by ``us`` (surface nodes) into ``path``."""
    import pyvista as pv

    surf = _surface(se)
    base, scale = surf.points.copy(), _field_scale(surf, us, amplitude)
    moved = surf.copy()
    moved.points = base + scale * us
    moved["|u|"] = np.linalg.norm(us, axis=1)
    p = pv.Plotter(off_screen=True, window_size=window_size)
    p.add_mesh(surf, style="wireframe", color="grey", opacity=0.35)
    p.add_mesh(moved, scalars="|u|", cmap="viridis", show_scalar_bar=True)
    p.add_title(title, font_size=12)
    p.view_isometric()
    p.camera.zoom(1.1)

    def move(phase):
        moved.points = base + phase * scale * us

    return save_picture(p, path, n_frames, move)


def render_mode(se: Superelement, mode: int, path=None, boundary: str | None = None,
                **options) -> Path | None:
    """Picture of mode ``mode`` (1-based) with its frequency in the title.

    ``boundary`` defaults to ``"fixed"`` (Craig-Bampton modes) when the superelement
    has that many modes, else ``"free"`` (elastic modes of the free part).
    """
    if boundary is None:
        boundary = "fixed" if mode <= se.n_modes else "free"
    freq, u = mode_shape(se, mode, boundary)
    kind = "fixed-interface" if boundary == "fixed" else "free"
    title = f"{kind} mode {mode}: {freq:.2f} Hz"
    return render_field(se, u, path, title, **options)


def write_mode(se: Superelement, mode: int, path, boundary: str | None = None,
               amplitude: float | None = None) -> Path:
    """Mode ``mode`` (1-based) on the surface mesh as a ``.vtu`` or ``.vtk`` file
    (:func:`~flexarm.reduction.mode_file.write_mode_mesh`: point data ``mode_shape`` in
    the link frame, mass-normalised with the superelement's ``M`` or scaled to a largest
    displacement of ``amplitude`` [m]; the mode number, frequency and scale as field
    data).  In ParaView: *Warp By Vector* on ``mode_shape``.  ``boundary`` as in
    :func:`render_mode`.
    """
    if boundary is None:
        boundary = "fixed" if mode <= se.n_modes else "free"
    if Path(path).suffix.lower() not in MODE_EXTENSIONS:  # before the solve
        raise ValueError(f"mode-shape file must be {' or '.join(MODE_EXTENSIONS)}, got '{path}'")
    freq, q = mode_coordinates(se, mode, boundary)
    _surface(se)  # a superelement without a surface mesh fails with its one-line reason
    u = se.expand(q)[se.surface_nodes]
    return write_mode_mesh(path, se.surface_points, se.surface_faces, u, mode, freq, amplitude)
