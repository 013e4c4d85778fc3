"""matplotlib figures whose PNG files come from the picture cache.

Every figure made through :func:`flexarm.fe.plotting.pyplot` is a :class:`CachedFigure`.
Its key is the figure itself, pickled (every artist with its data, limits, styles and
layout request) with the memory addresses matplotlib keeps in its transform tree left
out, plus the ``savefig`` options, ``rcParams`` and the matplotlib and Pillow versions.
Its ``tight_layout`` is only noted and done just before an actual draw, so a figure
served from the cache is never laid out; call it last, after every artist is added.
"""

from __future__ import annotations

import io
import logging
import os
import pickle
from pathlib import Path

import matplotlib
from matplotlib.figure import Figure
from matplotlib.transforms import TransformNode

from .picture_cache import cached_picture, picture_key

__all__ = ["CachedFigure", "figure_fingerprint"]

log = logging.getLogger(__name__)


class _StablePickler(pickle.Pickler):
    """Pickles a figure without the ``id()`` keys of each transform's parent map (they
    change from run to run; the parents themselves are kept, in order)."""

    def reducer_override(self, obj):
        if isinstance(obj, TransformNode):
            rv = obj.__reduce_ex__(pickle.HIGHEST_PROTOCOL)
            state = dict(rv[2])
            state["_parents"] = list(state.get("_parents", {}).values())
            return (rv[0], rv[1], state, *rv[3:])
        return NotImplemented


def figure_fingerprint(fig: Figure) -> bytes:
    """The bytes that decide what ``fig`` draws: the pickled figure (same content,
    same bytes, in any process) and the current ``rcParams``.

    Raises whatever pickling raises for a figure holding an unpicklable object (a
    formatter made from a lambda): such a figure is drawn, not cached.
    """
    buf = io.BytesIO()
    _StablePickler(buf, pickle.HIGHEST_PROTOCOL).dump(fig)
    buf.write(repr(sorted(matplotlib.rcParams.items())).encode())
    return buf.getvalue()


class CachedFigure(Figure):
    """A matplotlib figure whose PNG files come from the picture cache when an equal
    figure was saved before with the same options (any other format is drawn)."""

    def tight_layout(self, *, pad=1.08, h_pad=None, w_pad=None, rect=None):
        """Lay the axes out tightly, just before the figure is actually drawn."""
        self._pending_tight = {"pad": pad, "h_pad": h_pad, "w_pad": w_pad, "rect": rect}

    def savefig(self, fname, **kwargs):
        """``Figure.savefig``, served from the cache for a ``.png`` file."""
        is_file = isinstance(fname, str | os.PathLike)
        fmt = kwargs.get("format") or (Path(fname).suffix[1:].lower() if is_file else "")
        if not is_file or fmt != "png":
            return self._draw(fname, **kwargs)
        try:
            fingerprint = figure_fingerprint(self)
        except Exception as exc:  # noqa: BLE001 - any figure that will not pickle is drawn
            log.debug("figure not cacheable (%s): drawn", exc)
            return self._draw(fname, **kwargs)
        key = picture_key("matplotlib", fingerprint, sorted(kwargs.items()),
                          libraries=("matplotlib", "pillow"))
        cached_picture(fname, key, lambda p: self._draw(p, **kwargs),
                       lambda p, data: self._serve(p, data, kwargs))
        return None

    def _draw(self, fname, **kwargs):
        pending = self.__dict__.pop("_pending_tight", None)
        if pending is not None:
            Figure.tight_layout(self, **pending)
        return Figure.savefig(self, fname, **kwargs)

    def _serve(self, fname, data: bytes, kwargs: dict) -> None:
        """Write ``data`` through ``Figure.savefig`` with a canvas that prints the stored
        bytes instead of drawing: whatever wraps or watches ``savefig`` still sees
        every picture saved."""
        canvas = self.canvas
        self.canvas = _StoredCanvas(data)
        try:
            Figure.savefig(self, fname, **kwargs)
        finally:
            self.canvas = canvas


class _StoredCanvas:
    """Stands in for the canvas while a cached picture is written."""

    def __init__(self, data: bytes):
        self._data = data

    def print_figure(self, fname, **_):
        Path(fname).parent.mkdir(parents=True, exist_ok=True)
        Path(fname).write_bytes(self._data)
