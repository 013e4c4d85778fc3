"""Thread control for BLAS around many small dense products."""

from __future__ import annotations

import contextlib
import functools

__all__ = ["one_blas_thread"]


@functools.cache
def _controller():
    """One threadpoolctl controller per process: building one scans every loaded library,
    which costs milliseconds, and the small products it guards are called thousands of
    times (None without threadpoolctl)."""
    try:
        from threadpoolctl import ThreadpoolController
    except ImportError:  # pragma: no cover - threadpoolctl is a declared dependency
        return None
    return ThreadpoolController()


def one_blas_thread():
    """Context limiting BLAS (OpenBLAS, MKL) to one thread; a no-op without threadpoolctl.

    Many small products (per-pose maps, the inner steps of ARPACK) gain nothing from
    threads and lose to their start-up and to a second core that is often busy.

    Examples
    --------
    >>> import numpy as np
    >>> with one_blas_thread():
    ...     float((np.eye(3) @ np.ones(3)).sum())
    3.0
    """
    controller = _controller()
    if controller is None:  # pragma: no cover
        return contextlib.nullcontext()
    return controller.limit(limits=1, user_api="blas")
