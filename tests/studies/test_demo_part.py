"""The part-level step: the clamped bore of the built-in link, and the whole step on a
coarse mesh."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.fe import TetMesh
from flexarm.studies.demo_part import hub_bore_nodes, part_step


def test_hub_bore_is_the_nodes_near_the_hub_axis():
    # 50 mm grid centred on the y axis: the axis and its four neighbours, every y level
    mesh = TetMesh.box((0.4, 0.2, 0.4), (8, 2, 8), origin=(-0.2, -0.1, -0.2))
    nodes = hub_bore_nodes(mesh)
    assert len(nodes) == 5 * 3
    assert np.all(np.hypot(mesh.points[nodes, 0], mesh.points[nodes, 2]) < 0.061)


@pytest.mark.slow
def test_part_step_writes_modes_and_superelement(tmp_path):
    said = []
    step = part_step(tmp_path, said.append, size=0.06)
    assert said[0].startswith("part: tetrahedralising") and len(said) == 4
    f = step.figures
    assert f["link_rigid_modes"] == 6 and f["link_superelement_dof"] == 22
    assert 100 < f["link_mass_kg"] < 120
    # clamping one hub lowers the first elastic frequency well below the free one
    assert 100 < f["link_first_clamped_Hz"] < f["link_first_free_Hz"] / 2
    free = (tmp_path / "link_free_modes.csv").read_text().splitlines()
    assert free[0] == "mode,freq_Hz,rigid" and len(free) == 1 + 16
    clamped = (tmp_path / "link_clamped_modes.csv").read_text().splitlines()
    assert clamped[0] == "mode,freq_Hz" and len(clamped) == 1 + 10
    for name in ("link.stl", "link.vtu", "link_quality.txt", "link_cb10.h5"):
        assert (tmp_path / name).stat().st_size > 0
