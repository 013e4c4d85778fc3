"""Shared type aliases (like trimesh's ``typed.py``)."""

from __future__ import annotations

from os import PathLike
from typing import Union

import numpy as np
import numpy.typing as npt
import scipy.sparse as sp

__all__ = ["ArrayLike", "FloatArray", "IntArray", "BoolArray", "Sparse", "PathType"]

ArrayLike = npt.ArrayLike
FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]
BoolArray = npt.NDArray[np.bool_]
Sparse = sp.csr_matrix | sp.csc_matrix | sp.csr_array | sp.csc_array
PathType = Union[str, "PathLike[str]"]
