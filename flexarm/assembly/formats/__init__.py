"""File formats of the arm at a pose, one module each, found by extension or name:
state-space models (:data:`state_space_registry`: MATLAB ``.mat``, NumPy ``.npz``) and
the arm's matrices for Nastran (:data:`matrices_registry`: binary ``.op4``, write only).
"""

from ...fe.formats import FormatRegistry
from . import mat, npz, op4

#: State-space model formats (:class:`~flexarm.fe.formats.FormatRegistry`).
state_space_registry = FormatRegistry("state-space model")
state_space_registry.register("mat", (".mat",), mat.read, mat.write)
state_space_registry.register("npz", (".npz",), npz.read, npz.write)

#: Formats of the arm's K, M, damping and TCP map at a pose.
matrices_registry = FormatRegistry("arm matrices")
matrices_registry.register("op4", (".op4",), write=op4.write)


def read_state_space(path, file_format: str | None = None):
    """Read an :class:`~flexarm.assembly.state_space.ArmStateSpace` (``.mat``, ``.npz``).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from flexarm.assembly.examples import two_link_arm
    >>> from flexarm.assembly.state_space import state_space
    >>> ss = state_space(two_link_arm(), [0.0, 0.5])
    >>> p = write_state_space(pathlib.Path(tempfile.mkdtemp()) / "arm.mat", ss)
    >>> bool((read_state_space(p).A == ss.A).all())
    True
    """
    return state_space_registry.read(path, file_format)


def write_state_space(path, ss, file_format: str | None = None):
    """Write ``ss`` atomically in the format of ``path``'s extension or ``file_format``;
    returns the path."""
    return state_space_registry.write(path, ss, file_format)


__all__ = ["state_space_registry", "matrices_registry", "read_state_space",
           "write_state_space"]
