"""matplotlib for files, not windows: one place that selects the Agg backend, and makes
every figure a :class:`~flexarm.fe.cached_figure.CachedFigure` (a PNG of unchanged
content is copied from the cache instead of drawn again), and :func:`picture_from_inputs`,
which keys a plot function by its inputs before any figure is built (that saves the
figure's construction too: most of a warm redraw of a many-panel plot)."""

from __future__ import annotations

import functools
import hashlib
import logging
import pickle
from collections.abc import Callable
from pathlib import Path

from .cache import package_digest
from .errors import MissingDependencyError
from .picture_cache import cached_picture, picture_key

__all__ = ["picture_from_inputs", "pyplot", "save_figure"]

log = logging.getLogger(__name__)


def pyplot():
    """``matplotlib.pyplot`` on the non-interactive Agg backend (imported on first use).

    Plots are written to PNG files on machines without a display, so every plotting
    function asks for pyplot through here instead of selecting a backend itself.
    """
    try:
        import matplotlib
    except ImportError:
        raise MissingDependencyError("matplotlib", "plots") from None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return _CachingPyplot(plt)


class _CachingPyplot:
    """``matplotlib.pyplot`` whose new figures are ``CachedFigure`` (everything else is
    pyplot's own)."""

    def __init__(self, plt):
        self._plt = plt

    def __getattr__(self, name):
        return getattr(self._plt, name)

    def _with_class(self, kwargs: dict) -> dict:
        from .cached_figure import CachedFigure

        kwargs.setdefault("FigureClass", CachedFigure)
        return kwargs

    def figure(self, *args, **kwargs):
        return self._plt.figure(*args, **self._with_class(kwargs))

    def subplots(self, *args, **kwargs):
        return self._plt.subplots(*args, **self._with_class(kwargs))

    def subplot_mosaic(self, *args, **kwargs):
        return self._plt.subplot_mosaic(*args, **self._with_class(kwargs))


def save_figure(fig, path, dpi: int = 100, tight: bool = True, **savefig) -> Path:
    """Write ``fig`` to ``path`` (its folder made if needed), close it, return the path.

    ``tight`` lays the axes out first (``tight_layout``, skipped when the PNG comes from
    the picture cache); other keywords go to ``savefig`` (e.g. ``bbox_inches="tight"``).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> fig, ax = pyplot().subplots()
    >>> out = save_figure(fig, pathlib.Path(tempfile.mkdtemp()) / "sub" / "a.png")
    >>> out.name, out.stat().st_size > 0
    ('a.png', True)
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if tight:
        fig.tight_layout()
    fig.savefig(path, dpi=dpi, **savefig)
    pyplot().close(fig)
    return path


def _style() -> str:
    """matplotlib's ``rcParams`` as a plot will see them, without importing pyplot (half a
    second: a warm picture is a file copy).  The Agg backend is selected as
    :func:`pyplot` selects it; the ``backend`` entry itself is left out (it reads as a
    placeholder until pyplot is imported, and every picture is drawn on Agg)."""
    try:
        import matplotlib
    except ImportError:
        raise MissingDependencyError("matplotlib", "plots") from None
    matplotlib.use("Agg")
    return repr(sorted((k, v) for k, v in matplotlib.rcParams.items() if k != "backend"))


def picture_from_inputs(plot: Callable[..., Path]) -> Callable[..., Path]:
    """Decorate ``plot(path, *inputs, **options) -> path`` so that a ``.png`` it drew
    before from equal inputs is written from the cache without building the figure.

    The key is the function's name, the package digest (any change of flexarm's code
    draws again), the pickled inputs and options, matplotlib's ``rcParams`` and the
    versions of matplotlib and Pillow.  Inputs that do not pickle are drawn every time.
    ``plot`` must draw from its arguments only (no files read, no clock).

    Examples
    --------
    >>> import tempfile
    >>> calls = []
    >>> @picture_from_inputs
    ... def plot(path, values):
    ...     calls.append(values)
    ...     Path(path).write_bytes(b"png of " + repr(values).encode())
    ...     return Path(path)
    >>> folder = Path(tempfile.mkdtemp())
    >>> token = str(folder)  # inputs no earlier run has drawn
    >>> first = plot(folder / "a.png", [1, 2, token]).read_bytes()
    >>> plot(folder / "b.png", [1, 2, token]).read_bytes() == first
    True
    >>> len(calls)
    1
    """

    @functools.wraps(plot)
    def wrapper(path, *inputs, **options):
        if Path(path).suffix.lower() != ".png":
            return plot(path, *inputs, **options)
        try:
            blob = pickle.dumps((inputs, sorted(options.items())), pickle.HIGHEST_PROTOCOL)
        except Exception as exc:  # noqa: BLE001 - any input that will not pickle is drawn
            log.debug("inputs of %s not cacheable (%s): drawn", plot.__qualname__, exc)
            return plot(path, *inputs, **options)
        style = _style()
        key = picture_key("inputs", plot.__module__, plot.__qualname__, package_digest(),
                          hashlib.sha256(blob).hexdigest(), style,
                          libraries=("matplotlib", "pillow"))
        drawn = []
        out, _ = cached_picture(path, key, lambda p: drawn.append(plot(p, *inputs, **options)))
        return drawn[0] if drawn else out

    return wrapper
