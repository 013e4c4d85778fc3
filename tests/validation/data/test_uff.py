"""Universal files: a set written by pyuff's own writer from an analytic 3-DOF system is
read back exactly; our output read by pyuff gives what we wrote."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

from flexarm.fe.errors import ReadError
from flexarm.validation.data.formats import read_measurements
from flexarm.validation.data.formats.csv_points import read_points, write_points
from flexarm.validation.data.formats.uff import UffFrf, read_uff
from flexarm.validation.data.formats.uff_write import write_uff
from flexarm.validation.data.shape_data import Points, ShapeData

pyuff = pytest.importorskip("pyuff")

#: Frequency lines [Hz] exactly representable in pyuff's %13.5e abscissa.
FREQ = np.arange(1, 201) * 0.25
ZETA = 0.02


def three_dof():
    """Chain of three masses on springs (ground-1-2-3): modes and proportional damping."""
    m = np.diag([2.0, 1.5, 1.0])
    k1, k2, k3 = 4e4, 3e4, 2e4
    K = np.array([[k1 + k2, -k2, 0], [-k2, k2 + k3, -k3], [0, -k3, k3]])
    lam, Phi = sla.eigh(K, m)
    return np.sqrt(lam), Phi


def analytic_frf(freq, dof_out, dof_in):
    """Receptance [m/N] by modal superposition with ratio ``ZETA`` on every mode."""
    wr, Phi = three_dof()
    w = 2 * np.pi * np.asarray(freq)[:, None]
    den = wr**2 - w**2 + 2j * ZETA * wr * w
    return (Phi[dof_out] * Phi[dof_in] / den).sum(axis=1)


def pyuff_set(path, accel_node=None, mm=False):
    """Write 151, 164, 15, 58 (3 responses x 2 references) and 55 with pyuff itself.

    Node ``n`` (1, 2, 3) is mass ``n-1`` measured along ``y``; reference node 1 is
    excited along ``-y`` (UFF direction -2), so its FRFs change sign.  With ``mm`` the
    file is in mm (164 length factor 1000); ``accel_node`` writes that response as
    accelerance.
    """
    wr, Phi = three_dof()
    length = 1000.0 if mm else 1.0
    sets = [pyuff.prepare_151(model_name="three", description="analytic", db_app="test",
                              program="pyuff"),
            pyuff.prepare_164(units_code=4 if mm else 1, units_description="mm" if mm else "SI",
                              temp_mode=1, length=length, force=1.0, temp=1.0,
                              temp_offset=273.15),
            pyuff.prepare_15(node_nums=[1, 2, 3], def_cs=[0] * 3, disp_cs=[0] * 3,
                             color=[1] * 3, x=[0.0, 500.0, 1000.0], y=[0.0] * 3, z=[0.0] * 3)]
    for ref, ref_dir in ((1, -2), (3, 2)):
        for rsp in (1, 2, 3):
            H = analytic_frf(FREQ, rsp - 1, ref - 1) * np.sign(ref_dir) * length
            spec = 8
            if rsp == accel_node:
                H, spec = H * -(2 * np.pi * FREQ) ** 2, 12
            sets.append(pyuff.prepare_58(func_type=4, rsp_node=rsp, rsp_dir=2, ref_node=ref,
                                         ref_dir=ref_dir, data=H, x=FREQ,
                                         ordinate_spec_data_type=spec,
                                         orddenom_spec_data_type=13,
                                         abscissa_spec_data_type=18))
    for r in range(3):
        sets.append(pyuff.prepare_55(model_type=1, analysis_type=2, data_ch=2, spec_data_type=8,
                                     r1=np.zeros(3), r2=Phi[:, r], r3=np.zeros(3), load_case=1,
                                     mode_n=r + 1, freq=wr[r] / (2 * np.pi), node_nums=[1, 2, 3],
                                     modal_damp_vis=ZETA))
    pyuff.UFF(str(path)).write_sets(sets, mode="overwrite")
    return path


def as_written(x):
    """Values as pyuff's %13.5e text holds them (6 significant digits)."""
    return np.array([float(f"{v:13.5e}") for v in np.ravel(x)]).reshape(np.shape(x))


@pytest.mark.parametrize("mm", [False, True])
def test_pyuff_written_set_gives_analytic_frf_and_shapes(tmp_path, mm):
    content = read_uff(pyuff_set(tmp_path / "three.uff", accel_node=2, mm=mm), "rig",
                       np.zeros(6))
    frf, = content.frfs
    assert np.array_equal(frf.freq_hz, FREQ)
    assert frf.in_dirs.tolist() == ["y"] * 6 and frf.out_dirs.tolist() == ["y"] * 6
    for k in range(6):
        exact = analytic_frf(FREQ, frf.out_nodes[k] - 1, frf.in_nodes[k] - 1)
        assert np.max(np.abs(frf.H[k] - exact) / np.abs(exact)) < 1e-10
    outs, ins, A = frf.matrix()
    assert A.shape == (200, 3, 2) and outs == ["1y", "2y", "3y"] and ins == ["1y", "3y"]
    assert np.allclose(content.coordinates[:, 0], [0.0, 0.5, 1.0] if mm else [0, 500, 1000])
    wr, Phi = three_dof()
    s = content.shapes
    assert s.dofs == ["1y", "2y", "3y"]  # x and z are zero in every mode: not measured
    assert np.max(np.abs(s.shapes - as_written(Phi.T))) < 1e-12
    assert np.max(np.abs(s.freq_hz - as_written(wr / (2 * np.pi)))) < 1e-12
    assert np.all(s.damping_ratio == ZETA) and s.modes.tolist() == [1, 2, 3]
    assert content.header["program"].strip() == "pyuff"


def test_shapes_of_an_analytic_system_to_1e12(tmp_path):
    """Three equal masses, equal springs between them and to ground on each: the modes are
    (1, 1, 1), (1, 0, -1), (1, -2, 1) whatever k and k0, which pyuff's 6-digit 55 records
    hold exactly, so the shapes read back equal the analytic ones to round-off."""
    m, k, k0 = 1.5, 3e4, 1e4
    K = k * np.array([[1, -1, 0], [-1, 2, -1], [0, -1, 1]]) + k0 * np.eye(3)
    lam, Phi = sla.eigh(K, m * np.eye(3))
    np.testing.assert_allclose(lam, k0 / m + k / m * np.array([0.0, 1.0, 3.0]), rtol=1e-12)
    Phi = Phi / Phi[np.argmax(np.abs(Phi), axis=0), range(3)]  # largest entry +1
    sets = [pyuff.prepare_15(node_nums=[1, 2, 3], def_cs=[0] * 3, disp_cs=[0] * 3,
                             color=[1] * 3, x=[0.0, 0.5, 1.0], y=[0.0] * 3, z=[0.0] * 3)]
    for r in range(3):
        sets.append(pyuff.prepare_55(model_type=1, analysis_type=2, data_ch=2, spec_data_type=8,
                                     r1=np.zeros(3), r2=Phi[:, r], r3=np.zeros(3), load_case=1,
                                     mode_n=r + 1, freq=np.sqrt(lam[r]) / (2 * np.pi),
                                     node_nums=[1, 2, 3], modal_damp_vis=ZETA))
    path = tmp_path / "chain.uff"
    pyuff.UFF(str(path)).write_sets(sets, mode="overwrite")
    s = read_uff(path, "rig", np.zeros(6)).shapes
    analytic = np.array([[1.0, 1.0, 1.0], [1.0, 0.0, -1.0], [-0.5, 1.0, -0.5]])
    signs = np.sign(s.shapes[:, 0])[:, None] * np.sign(analytic[:, 0])[:, None]
    assert np.max(np.abs(s.shapes * signs - analytic)) < 1e-12
    assert np.max(np.abs(s.freq_hz / (np.sqrt(lam) / (2 * np.pi)) - 1)) < 1e-5  # 6 digits


def test_our_output_read_by_pyuff_is_identical(tmp_path):
    rng = np.random.default_rng(3)
    H = rng.standard_normal((4, 50)) + 1j * rng.standard_normal((4, 50))
    frf = UffFrf("P2", np.deg2rad([0, 0, 66, 0, -66, 0]), np.linspace(1.0, 50.0, 50),
                 np.array([1, 1, 2, 2]), np.array(["x", "y", "y", "z"]),
                 np.array([1, 1, 1, 1]), np.array(["y"] * 4), H * 1e-6)
    shapes = ShapeData(poses=["P2"] * 2, q=np.tile(frf.q, (2, 1)), modes=[1, 2],
                       freq_hz=[7.25, 16.5], damping_ratio=[0.02, 0.03], nodes=[1, 1, 2],
                       dirs=["x", "y", "z"], shapes=as_written(rng.standard_normal((2, 3))))
    for binary in (False, True):
        path = write_uff(tmp_path / f"ours{binary}.uff", shapes, [frf], nodes=[1, 2],
                         coordinates=[[1.0, 0.0, 1.5], [1.2, 0.0, 1.5]], binary=binary)
        sets = pyuff.UFF(str(path)).read_sets()
        assert [int(d["type"]) for d in sets] == [151, 164, 15, 55, 55, 58, 58, 58, 58]
        d58 = [d for d in sets if d["type"] == 58]
        for k, d in enumerate(d58):
            assert d["abscissa_spacing"] == 1  # even lines: first line and increment only
            assert np.array_equal(d["x"], frf.freq_hz)
            tol = 0 if binary else 5e-12
            assert np.max(np.abs(d["data"] - frf.H[k]) / np.abs(frf.H[k])) <= tol
        d55 = [d for d in sets if d["type"] == 55]
        assert np.array_equal(d55[1]["r3"], [0.0, shapes.shapes[1, 2]])
        assert np.array_equal(d55[0]["r1"], [shapes.shapes[0, 0], 0.0])
        back = read_uff(path)
        assert back.shapes == shapes
        assert back.frfs[0].pose == "P2" and np.allclose(back.frfs[0].q, frf.q, atol=1e-12)
        assert np.array_equal(back.frfs[0].H, np.array([d["data"] for d in d58]))
    assert read_measurements(path) == shapes


def test_errors_name_file_dataset_and_field(tmp_path):
    path = tmp_path / "bad.uff"
    pyuff.UFF(str(path)).write_sets([pyuff.prepare_58(
        func_type=1, rsp_node=1, rsp_dir=2, ref_node=1, ref_dir=2, data=np.ones(4) + 0j,
        x=np.arange(4.0), ordinate_spec_data_type=8, orddenom_spec_data_type=13,
        abscissa_spec_data_type=18)], mode="overwrite")
    with pytest.raises(ReadError, match=r"bad.uff, dataset 1 \(type 58\), field 'func_type'"):
        read_uff(path)
    pyuff.UFF(str(path)).write_sets([pyuff.prepare_58(
        func_type=4, rsp_node=1, rsp_dir=5, ref_node=1, ref_dir=2, data=np.ones(4) + 0j,
        x=np.arange(4.0), ordinate_spec_data_type=8, orddenom_spec_data_type=13,
        abscissa_spec_data_type=18)], mode="overwrite")
    with pytest.raises(ReadError, match=r"dataset 1 \(type 58\), field 'rsp_dir'"):
        read_uff(path)
    path.write_text("    -1\n    58\n garbage\n")
    with pytest.raises(ReadError, match="bad.uff"):
        read_uff(path)


def test_points_table_round_trip(tmp_path):
    pts = Points(nodes=[3, 1], links=[6, 2], positions=[[0.1, 0.0, 0.0], [0.0, 0.05, 0.45]])
    assert read_points(write_points(tmp_path / "p.csv", pts)) == pts


def test_complex_shapes_and_2411_nodes(tmp_path):
    """Complex modes (55, analysis type 3) keep frequency and damping through the
    eigenvalue; 2411 nodes read like 15 nodes."""
    shapes = ShapeData(poses=["Q1"] * 2, q=np.zeros((2, 6)), modes=[1, 2], freq_hz=[8.5, 21.0],
                       damping_ratio=[0.02, 0.05], nodes=[4, 4, 4], dirs=["x", "y", "z"],
                       shapes=[[1.0 + 0.1j, -0.5j, 0.25], [0.3, 1.0, -0.2 + 0.2j]])
    text = repr(shapes)  # the short line of ModalData, not every shape entry
    assert len(text) < 300 and text.startswith("ShapeData(") and "8.5" in text
    path = write_uff(tmp_path / "c.unv", shapes)
    d55 = [d for d in pyuff.UFF(str(path)).read_sets() if d["type"] == 55]
    assert [int(d["analysis_type"]) for d in d55] == [3, 3]
    back = read_uff(path).shapes
    assert np.allclose(back.freq_hz, shapes.freq_hz, rtol=1e-5)
    assert np.allclose(back.damping_ratio, shapes.damping_ratio, rtol=1e-4)
    assert np.array_equal(back.shapes, shapes.shapes)  # exact in 6 digits
    nodes = tmp_path / "n.uff"
    pyuff.UFF(str(nodes)).write_sets([pyuff.prepare_2411(
        node_nums=np.array([1, 2]), def_cs=np.zeros(2, int), disp_cs=np.zeros(2, int),
        color=np.ones(2, int), x=np.array([0.0, 0.5]), y=np.zeros(2), z=np.array([0.0, 0.25]))],
        mode="overwrite")
    content = read_uff(nodes)
    assert content.nodes.tolist() == [1, 2]
    assert np.array_equal(content.coordinates, [[0.0, 0.0, 0.0], [0.5, 0.0, 0.25]])
    with pytest.raises(ReadError, match="no mode shapes"):
        read_measurements(nodes)
