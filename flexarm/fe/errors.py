"""Domain errors shared by every layer (the base layer owns them).

One base class, :class:`FlexarmError`, so the CLI can turn any domain failure into
one clear line without a traceback.
"""

from __future__ import annotations

__all__ = [
    "FlexarmError",
    "MeshError",
    "InterfaceError",
    "ReadError",
    "ConvergenceError",
    "MissingDependencyError",
    "SingularMatrixError",
    "has_module",
    "require",
]


class FlexarmError(Exception):
    """Base class of every error flexarm raises on purpose."""


class MeshError(FlexarmError):
    """A mesh is unusable: empty, open, inverted, absurdly sized, ..."""


class InterfaceError(FlexarmError):
    """An interface region or coupling cannot carry its degrees of freedom."""


class ReadError(FlexarmError):
    """A file cannot be read; the message names the file (and line/column if known)."""


class ConvergenceError(FlexarmError):
    """An iterative solver stopped early.

    Attributes
    ----------
    eigenvalues, eigenvectors
        What did converge (may be empty), like SciPy's ``ArpackNoConvergence``.
    """

    def __init__(self, message: str, eigenvalues=None, eigenvectors=None):
        super().__init__(message)
        self.eigenvalues = eigenvalues
        self.eigenvectors = eigenvectors


class MissingDependencyError(FlexarmError):
    """An optional package is needed for this call and is not installed."""

    def __init__(self, package: str, purpose: str = ""):
        extra = f" for {purpose}" if purpose else ""
        super().__init__(f"the optional package '{package}' is needed{extra}: "
                         f"pip install {package}")
        self.package = package


class SingularMatrixError(FlexarmError):
    """The matrix is singular (for a stiffness: the part is not fully supported)."""


def has_module(package: str) -> bool:
    """True when the optional ``package`` can be imported (it is not imported here)."""
    import importlib.util

    return importlib.util.find_spec(package) is not None


def require(package: str, purpose: str = "") -> None:
    """Raise :class:`MissingDependencyError` unless the optional ``package`` is importable.

    >>> require("numpy")
    >>> require("no_such_package_here", "this example")
    Traceback (most recent call last):
    ...
    flexarm.fe.errors.MissingDependencyError: the optional package 'no_such_package_here' \
is needed for this example: pip install no_such_package_here
    """
    if not has_module(package):
        raise MissingDependencyError(package, purpose)

