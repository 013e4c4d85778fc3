"""matplotlib for files, not windows: one place that selects the Agg backend."""

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

    return plt


def save_figure(fig, path, dpi: int = 100, tight: bool = True, **savefig) -> Path:
    """Write ``fig`` to ``path`` (its folder made if needed), close it, return the path.

    ``tight`` lays the axes out first (``tight_layout``); other keywords go to
    ``savefig`` (e.g. ``bbox_inches="tight"``).

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
