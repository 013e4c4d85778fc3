"""A static test plan: poses, load levels and load directions, and the readings they give.

:class:`LabPlan` is what the virtual lab (:mod:`flexarm.validation.lab`) measures and
what test planning (:mod:`flexarm.validation.planning`) proposes; :func:`parse_loads`
and :func:`parse_dirs` read the command line's load levels [N] and directions (base
frame).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...fe.quantities import Quantity, parse_levels

__all__ = ["LabPlan", "parse_dirs", "parse_loads"]

_AXES = {"x": 0, "y": 1, "z": 2}


#: A load level [N] (a bare number is newtons; ``0.8kN`` with a unit).
LOAD_LEVEL = Quantity("force", "N", 0, 1e6)


def parse_loads(text: str, what: str = "loads") -> np.ndarray:
    """Load levels [N] from ``"0:800:100"`` (start:stop:step, inclusive) or ``"0,200,400"``,
    each finite and in 0..1e6 N, at most 1000 of them.

    Examples
    --------
    >>> parse_loads("0:800:400").tolist(), parse_loads("0,0.2kN").tolist()
    ([0.0, 400.0, 800.0], [0.0, 200.0])
    """
    return parse_levels(text, LOAD_LEVEL, what)


def parse_dirs(text: str) -> list[tuple[str, np.ndarray]]:
    """Load directions from ``"x,y,z,-z"``: (label, unit vector in the base frame)."""
    out = []
    for d in (t.strip().lower() for t in text.split(",") if t.strip()):
        sign = -1.0 if d.startswith("-") or d.endswith("-") else 1.0
        axis = d.strip("+-")
        if axis not in _AXES:
            raise ValueError(f"direction '{d}': expected x, y, z with optional sign")
        v = np.zeros(3)
        v[_AXES[axis]] = sign
        out.append((("-" if sign < 0 else "+") + axis, v))
    return out


@dataclass(frozen=True)
class LabPlan:
    """An experiment: poses (name -> q [rad]), load levels [N], directions, cycles."""

    poses: dict
    loads: np.ndarray
    dirs: list
    cycles: bool = False

    def rows(self) -> tuple[list[str], np.ndarray, np.ndarray, np.ndarray]:
        """Series labels, steps, q (n, 6) [rad], force (n, 3) [N] of every reading."""
        levels = np.asarray(self.loads, dtype=float)
        if self.cycles:
            levels = np.r_[levels, levels[-2::-1]]
        series, steps, qs, forces = [], [], [], []
        for pname, q in self.poses.items():
            for dname, v in self.dirs:
                for k, f in enumerate(levels):
                    series.append(f"{pname}_{dname}")
                    steps.append(k)
                    qs.append(q)
                    forces.append(f * v)
        return series, np.array(steps), np.array(qs, float), np.array(forces, float)
