"""A mode shape on a surface mesh as a ``.vtu`` (or legacy ``.vtk``) file for ParaView,
its scale stated in the file.

Point data ``mode_shape`` (p, 3) is the displacement of each vertex and ``magnitude`` its
length, in the frame of the points.  The shape is written mass-normalised (its
generalised mass ``phi^T M phi`` on the model's coordinates is 1, Nastran's ``MASS``
normalisation) or scaled so that its largest vertex displacement is a given amplitude
[m].  Field data (one value each; read back by meshio from ``.vtu``, by VTK, PyVista and
ParaView from both):

- ``mode``: the mode number (1-based; a double in the legacy file);
- ``freq_hz``: its frequency [Hz];
- ``modal_mass``: the written shape's generalised mass ``phi^T M phi`` (1: mass-normalised);
- ``max_displacement``: its largest vertex displacement (the amplitude when scaled to one).

meshio writes neither format's field data, so it is added to the written file: a
``<FieldData>`` element of the ``UnstructuredGrid`` (ASCII arrays, exact decimal
representation) or a legacy ``FIELD FieldData`` block after the ``DATASET`` line.
"""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np

from ..fe.files import atomic_path
from ..fe.typing import ArrayLike, FloatArray

__all__ = ["MODE_EXTENSIONS", "scaled_shape", "write_mode_mesh"]

#: Mode-shape files for ParaView (and any VTK reader).
MODE_EXTENSIONS = (".vtu", ".vtk")


def scaled_shape(u: ArrayLike, amplitude: float | None = None) -> tuple[FloatArray, float]:
    """The mass-normalised shape ``u`` (p, 3) as written: unchanged (``amplitude`` None) or
    scaled to a largest vertex displacement of ``amplitude`` [m]; returns it and its
    generalised mass (1, or the square of the scale factor).

    Examples
    --------
    >>> u, m = scaled_shape([[0.0, 3.0, 4.0], [1.0, 0.0, 0.0]], amplitude=0.01)
    >>> u[0].tolist(), round(m, 12)
    ([0.0, 0.006, 0.008], 4e-06)
    """
    u = np.asarray(u, dtype=float)
    if amplitude is None:
        return u, 1.0
    if not amplitude > 0:
        raise ValueError(f"the mode-shape amplitude must be > 0 m, got {amplitude:g}")
    peak = float(np.linalg.norm(u, axis=1).max()) if u.size else 0.0
    if peak == 0.0:
        raise ValueError("the mode shape is zero on the surface: it cannot be scaled")
    s = amplitude / peak
    return u * s, s * s


def write_mode_mesh(path, points: ArrayLike, faces: ArrayLike, u: ArrayLike, mode: int,
                    freq_hz: float, amplitude: float | None = None,
                    cell_data: dict | None = None) -> Path:
    """Write the mass-normalised shape ``u`` (p, 3) on the triangles ``faces`` (f, 3) of
    ``points`` (p, 3) [m] to ``path`` (``.vtu`` or ``.vtk``, atomically), scaled by
    :func:`scaled_shape`, with the field data of the module docstring; ``cell_data``
    ``{name: (f,) array}`` is added per triangle.  Returns the path."""
    import meshio

    path = Path(path)
    ext = path.suffix.lower()
    if ext not in MODE_EXTENSIONS:
        raise ValueError(f"mode-shape file must be {' or '.join(MODE_EXTENSIONS)}, got '{path}'")
    shape, modal_mass = scaled_shape(u, amplitude)
    magnitude = np.linalg.norm(shape, axis=1)
    mesh = meshio.Mesh(np.asarray(points, dtype=float),
                       [("triangle", np.asarray(faces, dtype=np.int64))],
                       point_data={"mode_shape": shape, "magnitude": magnitude},
                       cell_data={k: [np.asarray(v)] for k, v in (cell_data or {}).items()})
    fields = {"mode": np.array([int(mode)], dtype=np.int32),
              "freq_hz": np.array([float(freq_hz)]),
              "modal_mass": np.array([modal_mass]),
              "max_displacement": np.array([float(magnitude.max()) if magnitude.size else 0.0])}
    with atomic_path(path) as tmp:
        meshio.write(tmp, mesh, file_format=ext[1:])
        data = tmp.read_bytes()
        tmp.write_bytes(_with_vtu_fields(data, fields) if ext == ".vtu"
                        else _with_vtk_fields(data, fields))
    return path


_VTU_TYPES = {np.dtype(np.int32): "Int32", np.dtype(np.float64): "Float64"}


def _with_vtu_fields(data: bytes, fields: dict) -> bytes:
    arrays = "".join(
        f'<DataArray type="{_VTU_TYPES[v.dtype]}" Name="{k}" NumberOfTuples="{v.size}" '
        f'format="ascii">{" ".join(repr(x.item()) for x in v)}</DataArray>\n'
        for k, v in fields.items())
    anchor = b"<UnstructuredGrid>\n"
    if data.count(anchor) != 1:
        raise RuntimeError("meshio wrote an unexpected VTU layout: no single "
                           "<UnstructuredGrid> to give the field data")
    return data.replace(anchor, anchor + f"<FieldData>\n{arrays}</FieldData>\n".encode())


def _with_vtk_fields(data: bytes, fields: dict) -> bytes:
    head = data.split(b"\n", 3)
    binary = head[2].strip().upper() == b"BINARY"
    block = f"FIELD FieldData {len(fields)}\n".encode()
    for k, v in fields.items():
        # all double: VTK reads a legacy "int" as 32 bits, meshio as 64, and VTK refuses
        # the "vtktypeint32" name here
        v = v.astype(float)
        block += f"{k} 1 {v.size} double\n".encode()
        if binary:  # legacy VTK binary is big-endian
            block += struct.pack(f">{v.size}d", *v.tolist()) + b"\n"
        else:
            block += (" ".join(repr(x) for x in v.tolist()) + "\n").encode()
    anchor = b"DATASET UNSTRUCTURED_GRID\n"
    if data.count(anchor) != 1:
        raise RuntimeError("meshio wrote an unexpected VTK layout: no single DATASET line "
                           "to give the field data")
    return data.replace(anchor, anchor + block, 1)
