"""The virtual lab writes a universal file (2411 nodes and 82 tracelines per pose, 55
shapes, 58 FRFs) and a points table; ``compare`` reads it back and pairs by MAC."""

from __future__ import annotations

import numpy as np
import pytest

from flexarm.cli import main
from flexarm.validation.data.formats.uff import read_uff
from flexarm.validation.dynamic.compare_shapes import ShapeComparison
from flexarm.validation.lab.virtual_lab import run_lab
from flexarm.validation.workflow import compare

pyuff = pytest.importorskip("pyuff")


@pytest.fixture(scope="module")
def lab_uff(tmp_path_factory):
    folder = tmp_path_factory.mktemp("lab_uff")
    lab = run_lab(poses="P1,P2", loads="0:800:400", dirs="y", modal=True, n_modes=6, seed=2)
    files = lab.write(folder / "static.csv", folder / "lab.uff")
    return lab, files


def test_lab_uff_holds_what_the_lab_made(lab_uff):
    lab, files = lab_uff
    assert files.points == files.modal.with_suffix(".points.csv")
    types = [int(t) for t in pyuff.UFF(str(files.modal)).get_set_types()]
    assert types[:3] == [151, 164, 2420] and types.count(55) == 12
    assert types.count(2411) == types.count(82) == 2 and 15 not in types
    assert types.count(58) == sum(len(f.H) for f in lab.frfs) == 2 * 36 * 3
    content = read_uff(files.modal)
    # pyuff writes 55 values with 6 significant digits and 58 with 12; a DOF that is
    # zero in every mode (link 1 along x: only z rotation and bearing tilt move it)
    # reads as not measured
    made = dict(zip(lab.shapes.dofs, lab.shapes.shapes.T, strict=True))
    dropped = sorted(set(made) - set(content.shapes.dofs))
    assert dropped == ["100x", "101x"] and all(np.all(made[d] == 0) for d in dropped)
    kept = np.array([made[d] for d in content.shapes.dofs]).T
    assert np.allclose(content.shapes.shapes, kept, rtol=6e-6, atol=6e-6 * np.abs(kept).max())
    assert content.shapes.poses.tolist() == lab.shapes.poses.tolist()
    assert np.allclose(content.shapes.q, lab.shapes.q, atol=1e-9)
    for got, made in zip(content.frfs, lab.frfs, strict=True):
        assert np.all(np.abs(got.H - made.H) <= 1e-10 * np.abs(made.H))  # zeros stay 0
        assert np.array_equal(got.freq_hz, made.freq_hz)
    for got, made in zip(content.geometry, lab.geometry, strict=True):
        assert got.pose == made.pose and np.array_equal(got.nodes, made.nodes)
        assert np.allclose(got.coordinates, made.coordinates, rtol=0, atol=1e-15)
        assert np.array_equal(got.lines, made.lines)


def test_compare_pairs_lab_shapes_by_mac(lab_uff, tmp_path):
    _, files = lab_uff
    cmp = compare(files.modal)
    assert isinstance(cmp, ShapeComparison)
    for pc in cmp.poses:
        assert pc.model.tolist() == list(range(6))
        assert np.all(np.diag(pc.mac[:, :6]) > 0.99)
    assert main(["compare", str(files.modal), "-o", str(tmp_path / "cmp")]) == 0
    for name in ("mac.csv", "pairs.csv", "comac.csv", "mac_P1.png", "automac_P2.png"):
        assert (tmp_path / "cmp" / name).stat().st_size > 0


def test_flexible_links_lab_shapes_through_the_recovery(tmp_path):
    """Hidden link flexibility: the lab's shapes come through the coarse flexible
    model's recovery; ``compare --flexible`` pairs them at MAC ~ 1, the E-model at
    lower frequencies (the links are missing) but still by shape."""
    from flexarm.validation.models import ValidationOptions

    lab = run_lab(effects=["links:c=1"], poses="P2", loads="0:800:800", dirs="y",
                  modal=True, n_modes=5, seed=1)
    files = lab.write(tmp_path / "static.csv", tmp_path / "lab.uff")
    flex = compare(files.modal, options=ValidationOptions(flexible=True))
    pc, = flex.poses
    assert pc.model.tolist() == list(range(5)) and np.all(pc.pair_mac > 0.99)
    rigid, = compare(files.modal).poses
    assert np.all(rigid.model[:4] == np.arange(4)) and np.all(rigid.pair_mac[:4] > 0.9)
    assert np.all(rigid.f_model[:4] > 1.05 * rigid.f_meas[:4])
