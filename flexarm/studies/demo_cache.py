"""The demo's own results kept between runs: what a warm run would only compute again.

Superelements, meshes and pictures are cached where they are made; what the demo adds on
top of them (the diagnosis of the shipped lab data, the joint-space maps, the accuracy
study) is a pure function of the package (its code and the built-in robot it ships) and of
the options the demo passes, so a second run reads it back instead of computing it.  The
tables and pictures are still written from the result, every run, by the same writers.

Entries go through the one cache (:mod:`flexarm.fe.cache`, kind ``"demo"``), pickled and
keyed by :func:`~flexarm.fe.cache.package_digest`: any change of the code or of the
shipped data computes them again.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import TypeVar

from ..fe.cache import PICKLE, cache_key, cached, lookup, package_digest

__all__ = ["demo_result", "is_warm", "mark_warm"]

log = logging.getLogger(__name__)

T = TypeVar("T")


def demo_result(name: str, compute: Callable[[], T], *inputs) -> T:
    """The demo result ``name``: from the cache when the package and ``inputs`` are those
    of a run that stored it, else ``compute()`` (then stored).

    Parameters
    ----------
    name : str
        What the result is (``"diagnosis"``, ``"emodel_map"``...); part of the key.
    compute : callable () -> picklable value
        Makes the result from the package's own data and ``inputs`` only (nothing read
        from the output folder, no wall-clock value the caller expects fresh).
    *inputs
        Everything else the result depends on (arrays by content, the rest by ``repr``).

    Examples
    --------
    >>> import tempfile
    >>> token = tempfile.mkdtemp()  # inputs no earlier run has used
    >>> demo_result("example", lambda: [1, 2], token)
    [1, 2]
    >>> demo_result("example", lambda: "computed again", token)
    [1, 2]
    """
    key = cache_key("demo-" + name, package_digest(), *inputs)
    entry = cached("demo", key, compute, PICKLE)
    log.info("demo: %s %s", name, "from the cache" if entry.is_hit else "computed")
    if entry.is_hit or entry.path is None:
        return entry.value
    # The run that computes it uses the value as every later run reads it back: a
    # picture's key pickles what it draws, and an unpickled array's dtype is another
    # object than NumPy's own (so pickled apart), which would give every picture drawn
    # from it a new key on the first warm run.
    stored = lookup("demo", key, PICKLE)
    return entry.value if stored is None else stored


def _complete_key(*inputs) -> str:
    return cache_key("demo-complete", package_digest(), *inputs)


def mark_warm(*inputs) -> None:
    """Note that a demo run with ``inputs`` completed: its results are in the cache."""
    cached("demo", _complete_key(*inputs), lambda: True, PICKLE)


def is_warm(*inputs) -> bool:
    """Whether a run of this package with ``inputs`` completed since the cache was last
    cleared (:func:`mark_warm`): a warm run's steps are mostly cache reads.

    Examples
    --------
    >>> import tempfile
    >>> token = tempfile.mkdtemp()  # inputs no earlier run has used
    >>> is_warm(token), mark_warm(token), is_warm(token)
    (False, None, True)
    """
    return lookup("demo", _complete_key(*inputs), PICKLE) is not None
