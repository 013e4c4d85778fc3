"""State-space models as MATLAB ``.mat`` (level 5), for ``ss`` in MATLAB or python-control.

In MATLAB: ``s = load('arm_P1.mat'); sys = ss(s.A, s.B, s.C, s.D, 'InputName',
s.input_names, 'OutputName', s.output_names);``.  Names and units are cell arrays of
char, ``q_rad`` the pose, ``units`` ``'SI'`` and ``description`` one line saying so.
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from ...fe.errors import ReadError
from ...fe.files import atomic_path
from ..state_space import ArmStateSpace, from_arrays, to_arrays

__all__ = ["read", "write"]


def _cell(strings) -> np.ndarray:
    out = np.zeros((1, len(strings)), dtype=object)
    out[0, :] = list(strings)
    return out


#: The 116-byte text field of the file header: fixed, where scipy writes the time of
#: writing, so that the same model gives the same bytes on every run.
HEADER_TEXT = b"MATLAB 5.0 MAT-file, written by flexarm (state-space model of an arm)".ljust(116)


def write(path, ss: ArmStateSpace) -> None:
    """Write ``ss`` to ``path`` (.mat) atomically; the same model gives the same bytes.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from flexarm.assembly.examples import two_link_arm
    >>> from flexarm.assembly.state_space import state_space
    >>> out = pathlib.Path(tempfile.mkdtemp())
    >>> write(out / "a.mat", state_space(two_link_arm(), [0.0, 0.5]))
    >>> write(out / "b.mat", state_space(two_link_arm(), [0.0, 0.5]))
    >>> (out / "a.mat").read_bytes() == (out / "b.mat").read_bytes()
    True
    """
    from scipy.io import savemat

    data = {k: (_cell(v) if isinstance(v, list) else v) for k, v in to_arrays(ss).items()}
    buf = io.BytesIO()
    savemat(buf, data, do_compression=False, oned_as="column")
    raw = bytearray(buf.getvalue())
    raw[:len(HEADER_TEXT)] = HEADER_TEXT
    with atomic_path(path) as tmp:
        tmp.write_bytes(bytes(raw))


def _strings(cell) -> list[str]:
    return [str(np.asarray(c).squeeze()) if np.asarray(c).size else ""
            for c in np.asarray(cell, dtype=object).ravel()]


def read(path) -> ArmStateSpace:
    """Read and check a state-space model written by :func:`write`."""
    from scipy.io import loadmat

    path = Path(path)
    try:
        d = loadmat(path)
    except (OSError, ValueError, TypeError) as exc:
        raise ReadError(f"{path}: not a MATLAB .mat file ({exc})") from None
    for k in ("input_names", "input_units", "output_names", "output_units", "state_names"):
        if k in d:
            d[k] = _strings(d[k])
    for k in ("omega", "damping", "q_rad"):
        if k in d:
            d[k] = np.asarray(d[k], dtype=float).ravel()
    if "model" in d:
        d["model"] = "".join(_strings(d["model"]))
    return from_arrays(d, str(path))
