"""matplotlib for files, not windows: one place that selects the Agg backend, and makes
every figure a :class:`~flexarm.fe.cached_figure.CachedFigure` (a PNG of unchanged
content is copied from the cache instead of drawn again)."""

from __future__ import annotations

from pathlib import Path

from .errors import MissingDependencyError

__all__ = ["pyplot", "save_figure"]


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
