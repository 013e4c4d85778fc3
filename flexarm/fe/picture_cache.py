"""Pictures cached by what they show: a redraw of unchanged content is a file copy.

A picture's key is a digest of everything that decides its pixels: the data drawn, the
drawing options and the versions of the libraries that draw it.  On a hit the stored
bytes are written to the target (identical to what a redraw wrote the first time); on a
miss ``draw(path)`` writes the file and its bytes are stored.  Entries live in the one
cache (:mod:`flexarm.fe.cache`, kind ``"pictures"``).

matplotlib figures are keyed by :mod:`flexarm.fe.cached_figure`, PyVista scenes by
:func:`flexarm.reduction.render.scene_key`.  A plot function decorated with
:func:`flexarm.fe.plotting.picture_from_inputs` is keyed by its inputs before any figure
is built.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from .cache import BYTES, cache_key, cached

__all__ = ["cached_picture", "picture_key"]

#: Version of the picture-key recipe: bump it when a key must change for all pictures.
_RECIPE = 1


def picture_key(*parts, libraries: tuple[str, ...] = ()) -> str:
    """Cache key of a picture from ``parts`` (arrays by content, else ``repr``) and
    the versions of ``libraries`` (PyPI names).

    >>> key = picture_key("a", 1.0)
    >>> key == picture_key("a", 1.0), key == picture_key("a", 2.0)
    (True, False)
    """
    return cache_key("pictures", _RECIPE, *parts, libraries=libraries)


def _write(path: Path, data: bytes) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(data)


def cached_picture(path, key: str, draw: Callable[[Path], None],
                   serve: Callable[[Path, bytes], None] = _write) -> tuple[Path, bool]:
    """Write the picture of ``key`` to ``path``: the stored bytes when the cache has
    them (through ``serve(path, data)``, which writes them by default), else
    ``draw(path)`` and store what it wrote.  Returns the path and whether it came
    from the cache.

    >>> import tempfile
    >>> folder = Path(tempfile.mkdtemp())
    >>> key = picture_key("doctest", str(folder))
    >>> cached_picture(folder / "a.png", key, lambda p: p.write_bytes(b"png"))[1]
    False
    >>> p, hit = cached_picture(folder / "b.png", key, lambda p: p.write_bytes(b"other"))
    >>> p.read_bytes(), hit
    (b'png', True)
    """
    path = Path(path)

    def compute() -> bytes:
        draw(path)
        return path.read_bytes()

    entry = cached("pictures", key, compute, BYTES)
    if entry.is_hit:
        serve(path, entry.value)
    return path, entry.is_hit

