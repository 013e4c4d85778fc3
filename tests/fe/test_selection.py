"""select_nodes grammar (min/max planes, the five comparisons, '&', 'all', node sets, the 1e-6
tolerance of '=') against node counts of a 4 x 1 x 1 box counted by hand."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.fe import TetMesh, select_nodes

#: 1.0 x 0.1 x 0.1 m, 4 cells along x: 5 x 2 x 2 = 20 nodes, 4 per x plane
BOX = TetMesh.box((1.0, 0.1, 0.1), (4, 1, 1)).with_node_sets({"tip": [16, 17, 18, 19]})


@pytest.mark.parametrize("expression, count", [
    ("all", 20),
    ("x=min", 4), ("x=max", 4), ("y=min", 10), ("z=max", 10),
    ("x<0.5", 8), ("x<=0.5", 12), ("x>0.5", 8), ("x>=0.5", 12), ("x=0.5", 4),
    ("x < 2.5e-1", 4), ("z>-1", 20), ("x=min & y=max & z=max", 1),
    ("x>=0.25&x<=0.75", 12), ("all & y=0.1", 10),
    # '=' and the closed comparisons allow 1e-6 of the part size (1 m here)
    ("x=0.5000004", 4), ("x=0.500002", None), ("x<=0.4999996", 12), ("x<0.4999996", 8),
])
def test_counts(expression, count):
    if count is None:
        with pytest.raises(ValueError, match="selects no nodes"):
            select_nodes(BOX, expression)
        return
    nodes = select_nodes(BOX, expression)
    assert nodes.size == count
    assert nodes.dtype.kind == "i" and np.all(np.diff(nodes) > 0)


def test_selected_nodes_satisfy_the_expression():
    p = BOX.points
    nodes = select_nodes(BOX, "x>0.3 & z=min")
    np.testing.assert_array_equal(nodes, np.flatnonzero((p[:, 0] > 0.3) & (p[:, 2] == 0.0)))
    np.testing.assert_array_equal(select_nodes(BOX, "y=max & z=max")[[0, -1]], [3, 19])


def test_node_set_combines_with_comparisons():
    np.testing.assert_array_equal(select_nodes(BOX, "tip"), select_nodes(BOX, "x=max"))
    np.testing.assert_array_equal(select_nodes(BOX, "tip & y=min"),
                                  select_nodes(BOX, "x=max & y=min"))


def test_min_max_need_equals():
    with pytest.raises(ValueError, match="^selection term 'x<max': use '=' with min/max$"):
        select_nodes(BOX, "x<max")


def test_empty_term():
    with pytest.raises(ValueError, match="^selection 'x=min & ' has an empty term$"):
        select_nodes(BOX, "x=min & ")


def test_tolerance_follows_the_part_size():
    """eps = 1e-6 x the largest box edge: a 1 km part accepts 0.5 mm, a 1 mm part does not."""
    big = BOX.scaled(1000.0)
    assert select_nodes(big, "x=500.0005").size == 4
    small = BOX.scaled(1e-3)
    assert select_nodes(small, "x=0.0005").size == 4
    with pytest.raises(ValueError, match="selects no nodes"):
        select_nodes(small, "x=0.000502")
