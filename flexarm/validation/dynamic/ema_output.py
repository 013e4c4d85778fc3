"""The files of an ``ema`` run, written whole or not at all.

The modal data (CSV or universal file), the stabilisation diagram and the synthesis
picture of every pose, and the lab's points table are built in a temporary folder beside
them and moved into place when every one is complete
(:func:`~flexarm.fe.files.writes_folder`): Ctrl-C or a full disk half way leaves the
output folder as it was, an older complete run in it included.
"""

from __future__ import annotations

import shutil
from pathlib import Path

from ...fe.files import writes_folder
from ...fe.typing import PathType
from ..data.formats.uff import EXTENSIONS

__all__ = ["write_ema"]


@writes_folder("folder")
def write_ema(folder: PathType, name: str, result, comments=(),
              points: PathType | None = None) -> list[Path]:
    """Write an :class:`~.ema.EmaResult` as ``folder/name`` with its pictures.

    Parameters
    ----------
    folder : path-like
        Output folder (created if missing; other files in it are kept).
    name : str
        File name of the modal data: ``.csv`` or a universal file (``.uff``, ``.unv``).
    result : EmaResult
        The identified modes.
    comments : sequence of str
        Comment lines of the modal file (the command that made it).
    points : path-like, optional
        The lab's points table, copied as ``<stem>.points.csv`` beside a CSV (a
        universal file carries its geometry itself).

    Returns
    -------
    list of Path
        The files written, at their final place.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> import numpy as np
    >>> from flexarm.validation.data.formats.uff_frf import UffFrf
    >>> from flexarm.validation.dynamic.ema import run_ema
    >>> f = np.arange(1.0, 100.0, 0.25)
    >>> w, wr = 2 * np.pi * f, 2 * np.pi * 40.0
    >>> one = np.array([1])
    >>> frf = UffFrf("P1", np.zeros(6), f, one, np.array(["z"]), one, np.array(["z"]),
    ...              1e-6 / (wr**2 - w**2 + 0.02j * wr * w)[None])
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "ema"
    >>> [p.name for p in write_ema(out, "modal.csv", run_ema([frf]))]
    ['modal.csv', 'modal.stabilisation_P1.png', 'modal.frf_P1.png']
    """
    target = Path(folder) / name
    files = [Path(result.write(target, comments=comments))]
    files += result.write_plots(Path(folder) / Path(name).stem)
    if points is not None and Path(points).exists() and target.suffix.lower() not in EXTENSIONS:
        files.append(Path(shutil.copyfile(points, target.with_suffix(".points.csv"))))
    return files
