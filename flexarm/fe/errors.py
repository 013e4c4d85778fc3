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
