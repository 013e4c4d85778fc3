"""Mode shapes of 2414 analysis datasets (how NX and other FE programs write them) and
the modal mass of 55 and 2414 sets.

A 2414 set is a mode shape when it holds data at nodes (dataset location 1) of a
normal-mode (analysis type 2) or complex-eigenvalue analysis (3, 7) whose values are
3- or 6-DOF vectors (data characteristic 2 or 3): x, y, z first, rotations after, which
flexarm does not use.  Its analysis-specific fields, as pyuff names them (pyuff reads a
2414 set that is not a frequency response generically):

- ``record12_field2`` frequency [Hz], ``record12_field4`` modal mass,
  ``record12_field5`` viscous damping ratio (normal modes);
- ``record13_field1``, ``record13_field2``: real and imaginary part of the eigenvalue
  [rad/s], ``record13_field3``/``4`` modal A (complex modes).

Other 2414 sets (static results, stresses, element data) are not modes and are left
alone.
"""

from __future__ import annotations

import numpy as np

from .uff_frf import Where

__all__ = ["is_mode_2414", "mode_2414", "modal_mass"]

_MODES = (2, 3, 7)  # normal mode, complex eigenvalue first and second order
_VECTORS = {2: 3, 3: 6}  # data characteristic -> values per node


def is_mode_2414(dset: dict) -> bool:
    """Whether a 2414 set holds a mode shape at nodes.

    Examples
    --------
    >>> is_mode_2414({"analysis_type": 2, "dataset_location": 1, "data_characteristic": 3})
    True
    >>> is_mode_2414({"analysis_type": 1, "dataset_location": 1, "data_characteristic": 3})
    False
    """
    return (int(dset.get("analysis_type", 0)) in _MODES
            and int(dset.get("dataset_location", 0)) == 1
            and int(dset.get("data_characteristic", 0)) in _VECTORS)


def mode_2414(where: Where, i: int, dset: dict):
    """(freq [Hz], damping ratio, node ids (k,), shape (k, 3)) of a 2414 mode-shape set
    (:func:`is_mode_2414`); modes are numbered in file order, as 55 sets are.

    Examples
    --------
    >>> from pathlib import Path
    >>> d = {"analysis_type": 2, "data_characteristic": 2, "data_type": 2,
    ...      "record12_field2": 7.5, "record12_field5": 0.02, "node_nums": [4],
    ...      "data_at_node": [[0.0, 1.0, -0.5]]}
    >>> f, zeta, nodes, phi = mode_2414(Where(Path("nx.unv")), 0, d)
    >>> f, zeta, nodes.tolist(), phi.tolist()
    (7.5, 0.02, [4], [[0.0, 1.0, -0.5]])
    """
    kind = int(dset["analysis_type"])
    per_node = _VECTORS[int(dset["data_characteristic"])]
    is_complex = int(dset.get("data_type", 2)) in (5, 6)
    width = per_node * (2 if is_complex else 1)
    values = dset.get("data_at_node")
    nodes = np.asarray(dset.get("node_nums", []), np.int64)
    if values is None or not len(nodes):
        raise where.error(i, 2414, "data_at_node", "no nodal values: export the mode shapes "
                          "at nodes (dataset location 1)")
    short = [k for k, v in enumerate(values) if len(v) != width]
    if short:
        raise where.error(i, 2414, "data_at_node", f"node {nodes[short[0]]} has "
                          f"{len(values[short[0]])} values, expected {width} (pyuff reads one "
                          "line per node: export complex 6-DOF shapes as 55 datasets)")
    data = np.array([np.asarray(v, float) for v in values])
    phi = data[:, 0:6:2] + 1j * data[:, 1:6:2] if is_complex else data[:, :3]
    if kind == 2:
        freq = float(dset.get("record12_field2", 0.0))
        if not freq > 0:
            raise where.error(i, 2414, "record12_field2", f"the frequency is {freq:g} Hz: "
                              "a normal mode needs a positive one")
        zeta = float(dset.get("record12_field5", 0.0))
    else:
        eig = complex(float(dset.get("record13_field1", 0.0)),
                      float(dset.get("record13_field2", 0.0)))
        if eig == 0:
            raise where.error(i, 2414, "record13_field1", "the eigenvalue is zero")
        freq, zeta = abs(eig) / (2 * np.pi), -eig.real / abs(eig)
    return freq, zeta, nodes, phi


def modal_mass(dset: dict) -> float:
    """The modal mass a 55 or 2414 mode set states (0: not given).  A complex mode's
    is ``Im(A) / (2 w_d)`` of its modal A (``2 i w_d m`` for a normal mode).

    Examples
    --------
    >>> modal_mass({"type": 55, "analysis_type": 2, "modal_m": 1.0})
    1.0
    >>> modal_mass({"type": 55, "analysis_type": 3, "eig": -1 + 50j, "modal_a": 300j})
    3.0
    """
    kind = int(dset.get("analysis_type", 0))
    if int(dset["type"]) == 55:
        if kind == 2:
            return float(dset.get("modal_m", 0.0))
        eig, a = complex(dset.get("eig", 0)), complex(dset.get("modal_a", 0))
    else:
        if kind == 2:
            return float(dset.get("record12_field4", 0.0))
        eig = complex(float(dset.get("record13_field1", 0.0)),
                      float(dset.get("record13_field2", 0.0)))
        a = complex(float(dset.get("record13_field3", 0.0)),
                    float(dset.get("record13_field4", 0.0)))
    return a.imag / (2 * eig.imag) if eig.imag else 0.0
