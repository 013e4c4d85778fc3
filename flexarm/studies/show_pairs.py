"""The two seats of every joint checked against each other on the tet meshes.

:func:`pair_rows` joins the CAD measure of each joint's seat pair
(:func:`~flexarm.robot.seat_pairs.seat_pairs`: the gap between the two seats' surface
centroids along the joint axis, the overlap of their radius ranges) with the FE nodes
each seat selects on its link's tet mesh (the rows of
:func:`~flexarm.studies.show_regions.show_regions`).  A pair is accepted when the gap is
within :data:`~flexarm.robot.seat_pairs.PAIR_GAP` and each side holds at least
:data:`MIN_PAIR_NODES` nodes: the three of a rank-6 coupling, twice over.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..robot.description import Robot
from ..robot.seat_mesh import MIN_SEAT_NODES
from ..robot.seat_pairs import SeatPair, seat_pairs

__all__ = ["MIN_PAIR_NODES", "PairRow", "pair_rows", "pairs_text"]

#: FE nodes each seat of a pair must hold on the tet mesh (the build refines the mesh
#: over a seat estimated to hold fewer: :mod:`flexarm.robot.seat_mesh`).
MIN_PAIR_NODES = MIN_SEAT_NODES


@dataclass(frozen=True)
class PairRow:
    """One joint: its :class:`~flexarm.robot.seat_pairs.SeatPair` (metres) and the FE
    nodes of the parent's and the child's seat (-1: that link's mesh was not looked at)."""

    pair: SeatPair
    parent_nodes: int
    child_nodes: int

    @property
    def status(self) -> str:
        """``ok``, ``review`` or what is wrong (one phrase)."""
        if not self.pair.ok:
            return self.pair.status
        few = [f"{n} FE nodes on {link}" for n, link in
               ((self.parent_nodes, self.pair.parent), (self.child_nodes, self.pair.child))
               if 0 <= n < MIN_PAIR_NODES]
        if few:
            return f"{' and '.join(few)} (< {MIN_PAIR_NODES})"
        return self.pair.status

    @property
    def ok(self) -> bool:
        """The seats face each other and each holds enough nodes (a review is ok)."""
        return self.status in ("ok", "ok (bore)", "ok (both ends)", "review")


def pair_rows(robot: Robot, rows) -> tuple[PairRow, ...]:
    """:class:`PairRow` of every joint of ``robot`` whose links have CAD, with the FE
    nodes of the region ``rows`` (objects with ``link``, ``region``, ``fe_nodes``)."""
    nodes = {(r.link, r.region): r.fe_nodes for r in rows}
    return tuple(PairRow(p, nodes.get((p.parent, p.joint), -1), nodes.get((p.child, p.joint), -1))
                 for p in seat_pairs(robot))


def pairs_text(pairs) -> str:
    """Table: joint, parent and child link, gap along the axis [mm], radial overlap [mm]
    (negative: a ring inside the other), FE nodes of each seat, status."""
    lines = ["seat pairs (gap along the joint axis between the two seats' CAD surface, "
             "overlap of their radius ranges)",
             f"{'joint':<20} {'parent':<14} {'child':<14} {'gap_mm':>7} {'overlap_mm':>10} "
             f"{'nodes_p':>7} {'nodes_c':>7}  status"]
    for row in pairs:
        p = row.pair
        nodes = [("-" if n < 0 else str(n)) for n in (row.parent_nodes, row.child_nodes)]
        lines.append(f"{p.joint:<20} {p.parent:<14} {p.child:<14} {1e3 * p.gap:>7.1f} "
                     f"{1e3 * p.overlap:>10.1f} {nodes[0]:>7} {nodes[1]:>7}  {row.status}")
    return "\n".join(lines)
