"""Universal files: a set written by pyuff's own writer from an analytic 3-DOF system is
read back exactly; our output read by pyuff gives what we wrote."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import scipy.linalg as sla

from flexarm.fe.errors import ReadError
from flexarm.validation.data.formats import read_measurements
from flexarm.validation.data.formats.csv_points import read_points, write_points
from flexarm.validation.data.formats.uff import UffFrf, read_uff
from flexarm.validation.data.formats.uff_geometry import PoseGeometry
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
        geometry = [PoseGeometry("P2", np.array([1, 2]),
                                 np.array([[1.0, 0.0, 1.5], [1.2, 0.0, 1.5]]), np.array([1, 2]))]
        path = write_uff(tmp_path / f"ours{binary}.uff", shapes, [frf], geometry, binary=binary)
        sets = pyuff.UFF(str(path)).read_sets()
        assert [int(d["type"]) for d in sets] == [151, 164, 2420, 2411, 82, 55, 55, 58, 58, 58,
                                                  58]
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


CORPUS = Path(__file__).resolve().parents[4] / "shared/data/uff/pyuff_tests"


def set_2414(r: int, values, freq: float, zeta: float) -> dict:
    """A normal-mode 2414 set of nodes 1-3 (3-DOF vectors) for pyuff's writer."""
    return {"type": 2414, "analysis_dataset_label": r + 1, "analysis_dataset_name": "modes",
            "dataset_location": 1, "id1": "analytic", "id2": "NONE", "id3": "NONE",
            "id4": "NONE", "id5": f"mode {r + 1}", "model_type": 1, "analysis_type": 2,
            "data_characteristic": 2, "result_type": 8, "data_type": 2,
            "number_of_data_values_for_the_data_component": 3, "record10_field6": r + 1,
            "record12_field2": freq, "record12_field4": 2.5, "record12_field5": zeta,
            "node_nums": np.array([1, 2, 3]), "data_at_node": [np.asarray(v) for v in values]}


def complex_2414(eig: complex, values) -> str:
    """A complex-mode 2414 set in NX's fixed format (pyuff's writer puts a negative
    eigenvalue 14 columns wide, which no fixed-format reader reads back)."""
    def ints(*v):
        return "".join(f"{x:10d}" for x in v)

    def reals(*v):
        return "".join(f"{x:13.5E}" for x in v)

    lines = ["    -1", "  2414", ints(1), "modes", ints(1), *["NONE"] * 5,
             ints(1, 3, 2, 8, 5, 3), ints(0, 0, 0, 0, 0, 1, 0, 0), ints(0, 0), reals(*[0.0] * 6),
             reals(eig.real, eig.imag, 0, 0, 0, 0)]
    for n, v in enumerate(values, 1):
        lines += [ints(n), reals(*[x for c in v for x in (c.real, c.imag)])]
    return "\n".join(lines + ["    -1", ""])


def test_2414_mode_shapes_of_an_analytic_system(tmp_path):
    """Normal modes of the 3-DOF chain written as 2414 sets (pyuff's writer, 6 digits)
    read back as the 55 sets would: frequencies, damping, shapes along y, modal mass;
    complex modes keep frequency and damping through the eigenvalue."""
    wr, Phi = three_dof()
    nodes = pyuff.prepare_2411(node_nums=np.array([1, 2, 3]), def_cs=np.zeros(3, int),
                               disp_cs=np.zeros(3, int), color=np.ones(3, int),
                               x=np.array([0.0, 0.5, 1.0]), y=np.zeros(3), z=np.zeros(3))
    sets = [nodes] + [set_2414(r, [[0.0, Phi[k, r], 0.0] for k in range(3)],
                               wr[r] / (2 * np.pi), ZETA) for r in range(3)]
    path = tmp_path / "nx.unv"
    pyuff.UFF(str(path)).write_sets(sets, mode="overwrite")
    content = read_uff(path, "rig", np.zeros(6))
    s = content.shapes
    assert s.dofs == ["1y", "2y", "3y"] and s.modes.tolist() == [1, 2, 3]
    assert np.max(np.abs(s.shapes - as_written(Phi.T))) < 1e-12
    assert np.max(np.abs(s.freq_hz - as_written(wr / (2 * np.pi)))) < 1e-12
    assert np.allclose(s.damping_ratio, ZETA, rtol=1e-12)
    assert content.modal_mass.tolist() == [2.5] * 3
    assert content.geometry[0].pose == "rig" and content.geometry[0].nodes.tolist() == [1, 2, 3]
    zeta, w = 0.05, 2 * np.pi * 12.0
    eig = w * complex(-zeta, np.sqrt(1 - zeta**2))
    pyuff.UFF(str(path)).write_sets([nodes], mode="overwrite")
    with path.open("a") as fh:
        fh.write(complex_2414(eig, [[0.5 + 0.25j, 1.0, -0.5j]] * 3))
    s = read_uff(path, "rig", np.zeros(6)).shapes
    assert np.isclose(s.freq_hz[0], 12.0, rtol=1e-5) and np.isclose(s.damping_ratio[0], zeta,
                                                                       rtol=1e-4)
    assert np.array_equal(s.shapes[0, :3], [0.5 + 0.25j, 1.0, -0.5j])


@pytest.mark.skipif(not CORPUS.exists(), reason=f"no universal files at {CORPUS}")
def test_nx_2414_and_testlab_82_files():
    """NX's 2411 + 2414 file: 10 modes from 0.956363 Hz, 441 nodes of a 1 m plate;
    Testlab's tracelines (82) come with its 15 nodes."""
    content = read_uff(CORPUS / "2411 and 2414.uff", "nx", np.zeros(6))
    s = content.shapes
    assert len(s.freq_hz) == 10 and s.freq_hz[0] == 0.956363 and s.freq_hz[1] == 2.34163
    assert np.all(content.modal_mass == 0)  # the file does not give one
    g, = content.geometry
    assert len(g.nodes) == 441 and np.array_equal(g.coordinates[0], [1.0, 0.0, 0.0])
    assert np.array_equal(s.shapes[0, :3][s.dirs[:3] == "z"], [-0.708571])
    testlab = read_uff(CORPUS / "TestLab 161 164 18 15 82.uff")
    g, = testlab.geometry
    assert len(g.nodes) == 36 and g.lines[:8].tolist() == [2, 5, 6, 3, 4, 1, 2, 3]
    assert set(g.lines[g.lines > 0]) <= set(g.nodes.tolist())


def test_coherence_weights_the_frf_comparison(tmp_path):
    """A receptance equal to the model's except for one band 10^4 too large, where the
    coherence is 0.1 (0.99 elsewhere), written with its coherence and read back: the
    weighted RMS of log10 |H_meas / H_model| is 4 sqrt(n_b w_b / (n_b w_b + n_g w_g))
    with w = gamma^2 / (1 - gamma^2) (unweighted: 4 sqrt(n_b / n)), and the peak is
    looked for where the coherence is good."""
    from dataclasses import replace

    from flexarm.assembly.analyses import frf
    from flexarm.assembly.examples import two_link_arm
    from flexarm.validation.data.formats import UffOptions
    from flexarm.validation.data.formats.uff import read
    from flexarm.validation.dynamic.compare import compare_frf

    arm = two_link_arm()
    f = np.arange(2, 201) * 0.5
    H = frf(arm, np.zeros(2), f)[:, 1, 1]
    bad = (f >= 60) & (f <= 70)
    g2 = np.where(bad, 0.1, 0.99)
    meas = np.where(bad, 1e4, 1.0) * H
    path = write_uff(tmp_path / "coh.uff", frfs=[UffFrf(
        "A", np.zeros(6), f, np.array([7]), np.array(["y"]), np.array([7]), np.array(["y"]),
        meas[None], g2[None])])
    assert [int(t) for t in pyuff.UFF(str(path)).get_set_types()][-2:] == [58, 58]
    data = read(path, uff=UffOptions(tcp_node=7))
    assert np.array_equal(data.coherence, g2)
    cmp = compare_frf(arm, data)
    row, = cmp.table
    assert "weighted by the measured coherence" in cmp.text()
    nb, ng, wb, wg = bad.sum(), (~bad).sum(), 0.1 / 0.9, 0.99 / 0.01
    assert np.isclose(row.rms_log10_mag, 4 * np.sqrt(nb * wb / (nb * wb + ng * wg)), rtol=1e-9)
    assert row.peak_meas_hz == f[~bad][np.argmax(np.abs(H[~bad]))] == row.peak_model_hz
    plain, = compare_frf(arm, replace(data, coherence=None)).table
    assert np.isclose(plain.rms_log10_mag, 4 * np.sqrt(nb / len(f)), rtol=1e-9)
    assert 60 <= plain.peak_meas_hz <= 70


def test_coherence_of_an_analyzer_file_follows_its_frf(tmp_path):
    """An accelerance and its coherence from 0 Hz, as an FFT analyzer exports them: the
    0 Hz line goes with the FRF's, the other lines keep their coherence; a coherence
    without FRFs is refused naming the fix."""
    f = np.arange(0, 41) * 0.5
    g2 = np.linspace(0.5, 1.0, f.size)
    common = dict(rsp_node=1, rsp_dir=2, ref_node=1, ref_dir=-2, x=f, abscissa_spec_data_type=18)
    sets = [pyuff.prepare_58(func_type=4, data=np.r_[0, np.ones(40)] + 0j,
                             ordinate_spec_data_type=12, orddenom_spec_data_type=13, **common),
            pyuff.prepare_58(func_type=6, data=g2, ordinate_spec_data_type=0,
                             orddenom_spec_data_type=0, **common)]
    path = tmp_path / "analyzer.uff"
    pyuff.UFF(str(path)).write_sets(sets, mode="overwrite")
    got, = read_uff(path, "rig", np.zeros(6)).frfs
    assert np.array_equal(got.freq_hz, f[1:])
    assert np.allclose(got.coherence, g2[None, 1:], rtol=1e-12, atol=0)
    pyuff.UFF(str(path)).write_sets(sets[1:], mode="overwrite")
    with pytest.raises(ReadError, match=r"dataset 1 \(type 58\), field 'func_type': coherence"
                                        r".*export the FRFs"):
        read_uff(path, "rig", np.zeros(6))
