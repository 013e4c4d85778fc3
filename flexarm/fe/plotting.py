"""matplotlib for files, not windows: one place that selects the Agg backend."""

from __future__ import annotations

from .errors import MissingDependencyError

__all__ = ["pyplot"]


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
