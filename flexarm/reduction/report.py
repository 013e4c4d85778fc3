"""Text summaries of a superelement and of the reduction that made it."""

from __future__ import annotations

import numpy as np

from ..fe.text import text_table
from .reduce import ReductionStats
from .superelement import Superelement

__all__ = ["superelement_text", "reduction_text"]

#: Steps of a reduction, in the order they run.
_STEPS = ("assemble_couple", "factorise", "constraint_modes", "eigen", "projection", "total")


def superelement_text(se: Superelement, name: str = "superelement") -> str:
    """Method, DOF count, mass [kg] and centre of mass [m], a table of its interfaces
    (master nodes, position [m]) and its fixed-interface frequencies [Hz].

    Examples
    --------
    >>> from flexarm.fe import MATERIALS, TetMesh
    >>> from flexarm.reduction import CylinderRegion, reduce_part
    >>> mesh = TetMesh.box((0.4, 0.04, 0.04), (8, 2, 2))
    >>> ends = [CylinderRegion(n, (x, 0.02, 0.02), (1, 0, 0), 0.0, 0.04, 1e-6)
    ...         for n, x in (("a", 0.0), ("b", 0.4))]
    >>> print(superelement_text(reduce_part(mesh, MATERIALS["steel"], ends, "rbe2", "guyan"),
    ...                         "bar.h5"))
    bar.h5: guyan (rbe2), 12 DOF = 12 interface + 0 modal; mass 5.024 kg, COM [0.2  0.02 0.02] m
    interface  nodes      position [m]
    ---------  -----  ----------------
            a      1  [0.   0.02 0.02]
            b      1  [0.4  0.02 0.02]
    """
    lines = [f"{name}: {se.method} ({se.coupling}), {se.n_dofs} DOF = {se.n_boundary} interface "
             f"+ {se.n_modes} modal; mass {se.mass:.6g} kg, COM {np.round(se.center_of_mass, 6)} m",
             text_table(["interface", "nodes", "position [m]"],
                        [[n, int(np.sum(se.node_interface == i)),
                          np.array2string(se.interface_positions[i], precision=4)]
                         for i, n in enumerate(se.interface_names)])]
    if se.n_modes:
        lines.append("fixed-interface frequencies [Hz]: "
                     + ", ".join(f"{f:.6g}" for f in se.freq_hz))
    return "\n".join(lines)


def reduction_text(se: Superelement, stats: ReductionStats) -> str:
    """DOF counts (full FE, coupled, superelement), the region nodes and position [m] of each
    interface, the fixed-interface frequencies [Hz] and the wall time of each step [s]."""
    lines = [text_table(["", "DOF"], [["full FE model", stats.n_full],
                                      ["coupled", stats.n_coupled],
                                      ["superelement", stats.n_reduced]]),
             text_table(["interface", "region nodes", "position [m]"],
                        [[n, stats.region_nodes[n], np.array2string(p, precision=4)]
                         for n, p in zip(se.interface_names, se.interface_positions,
                                         strict=True)])]
    if se.n_modes:
        lines.append(text_table(["mode", "fixed-interface freq [Hz]"],
                                [[i + 1, float(f)] for i, f in enumerate(se.freq_hz)]))
    steps = [k for k in _STEPS if k in stats.seconds]
    lines.append(text_table(["step", "time [s]"], [[k, float(stats.seconds[k])] for k in steps],
                            "{:.3f}"))
    return "\n".join(lines)
