"""Thread control for BLAS around many small dense products."""

from __future__ import annotations

import contextlib

__all__ = ["one_blas_thread"]


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
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover - threadpoolctl is a declared dependency
        return contextlib.nullcontext()
    return threadpool_limits(1, user_api="blas")
