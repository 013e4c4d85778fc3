"""What the commands write: the CSV behind every PNG (the plotted numbers, read back from
the figure objects), mode shapes for ParaView, format conversion, and CLI habits."""

import time
from pathlib import Path

import numpy as np
import pytest

from flexarm.cli import main
from flexarm.fe import TetMesh
from flexarm.meshes import write_volume_mesh
from flexarm.reduction import formats

IFACES = ["--interface", "a:0,0.02,0.02,1,0,0,0.04,1e-6",
          "--interface", "b:0.4,0.02,0.02,1,0,0,0.04,1e-6"]


def _csv(path) -> dict:
    head = Path(path).read_text().splitlines()[0].split(",")
    rows = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return dict(zip(head, rows.T, strict=True))


def test_frf_csv_is_the_bode_plot(tmp_path, figures, capsys):
    assert main(["frf", "--pose", "P2", "--fmax", "50", "-o", str(tmp_path)]) == 0
    d = _csv(tmp_path / "frf.csv")
    amp, phase = figures["frf_bode.png"].axes
    text = capsys.readouterr().out.splitlines()
    for k, (line, name) in enumerate(zip(amp.get_lines(), "xyz", strict=True)):
        h = d[f"re_H{name}{name}_m_per_N"] + 1j * d[f"im_H{name}{name}_m_per_N"]
        np.testing.assert_allclose(line.get_xdata(), d["freq_Hz"], rtol=1e-9)
        np.testing.assert_allclose(line.get_ydata(), np.abs(h) * 1e6, rtol=1e-9)
        # the table speaks the plot's unit: its peak is the plotted curve's maximum
        assert float(text[1 + k].split()[3]) == pytest.approx(line.get_ydata().max(), abs=1e-4)
    assert amp.get_ylabel() == "|H| [mm/kN]" and "E-model" in amp.get_title()
    assert "P2" in amp.get_title() and len(phase.get_legend().get_texts()) == 3


def test_compliance_csv_is_the_printed_matrix(tmp_path, capsys):
    assert main(["compliance", "--pose", "P1", "-o", str(tmp_path)]) == 0
    printed = capsys.readouterr().out.splitlines()[1:4]
    C = np.loadtxt(tmp_path / "compliance.csv", delimiter=",", skiprows=1,
                   usecols=range(1, 7))
    np.testing.assert_allclose(C[:3, :3] * 1e6,
                               [[float(v) for v in row.split()[1:]] for row in printed],
                               atol=1e-4)


def test_modes_csv_is_the_bar_chart(tmp_path, figures):
    assert main(["modes", "--pose", "P1", "-o", str(tmp_path)]) == 0
    d = _csv(tmp_path / "mode_energy.csv")
    ax = figures["mode_energy.png"].axes[0]
    shares = [c for c in d if c.startswith("energy_share_")]
    assert len(ax.containers) == len(shares) == 6
    for bars, col in zip(ax.containers, shares, strict=True):
        np.testing.assert_allclose([b.get_height() for b in bars], d[col], rtol=1e-9,
                                   atol=1e-12)
    np.testing.assert_allclose([float(t.get_text()) for t in ax.get_xticklabels()],
                               d["f_Hz"], atol=0.051)
    assert "P1" in ax.get_title() and "E-model" in ax.get_title()


def test_map_csv_log_scale_and_no_singular_stiffest(tmp_path, figures, capsys):
    from matplotlib.colors import LogNorm

    assert main(["map", "--n", "30", "--no-frequencies", "-o", str(tmp_path)]) == 0
    text = capsys.readouterr().out
    d = _csv(tmp_path / "map.csv")
    sing = d["near_singular"] == 1
    assert 0 < sing.sum() < 0.5 * sing.size and (d["jacobian_cond"][sing] > 20).all()
    # poses the demo arm cannot take (links in each other or the floor) are masked too
    hit = d["collides"] == 1
    assert 0 < hit.sum() < 0.5 * hit.size and f"{int(hit.sum())} of 900 grid poses" in text
    sing = sing | hit
    # the stiffest pose printed is the CSV's largest Kxx among the poses not masked
    line = next(s for s in text.splitlines() if s.startswith("stiffest in x"))
    assert float(line.split("Kxx=")[1].split()[0]) == pytest.approx(
        d["kxx_N_per_mm"][~sing].max(), abs=0.5)
    assert d["kxx_N_per_mm"][sing].max() > d["kxx_N_per_mm"][~sing].max()
    assert "singularity" in text
    fig = figures["map_Kxx_heat.png"]
    ax = fig.axes[0]
    mesh = ax.collections[0]
    assert isinstance(mesh.norm, LogNorm)
    Z = mesh.get_array()  # (n_a, n_b) masked where singular, in the CSV's row order
    np.testing.assert_array_equal(np.ma.getmaskarray(Z).ravel(), sing)
    np.testing.assert_allclose(Z.compressed(), d["kxx_N_per_mm"][~sing], rtol=1e-9)
    assert ax.get_title() == "E-model Kxx over (q2, q3) at P1"
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels[0] == "pose P1" and "near-singular" in labels[1]
    star = ax.get_lines()[0]
    assert (star.get_xdata()[0], star.get_ydata()[0]) == pytest.approx((-19.0, 52.0))


def test_chatter_csv_is_the_plot_and_stays_in_range(tmp_path, figures):
    from flexarm.studies.contact.chatter_study import ORBIT_LIMIT

    assert main(["chatter", "--kc", "5e5", "--pose", "P1", "-o", str(tmp_path)]) == 0
    d = _csv(tmp_path / "chatter_time.csv")
    assert list(d) == ["t_s", "robot_x1_m", "robot_x2_m", "cnc_x1_m", "cnc_x2_m"]
    robot = np.hypot(d["robot_x1_m"], d["robot_x2_m"])
    assert np.isnan(robot).any() and np.nanmax(robot) <= ORBIT_LIMIT  # it chatters
    orbit = figures["chatter_orbit.png"].axes[0]
    np.testing.assert_allclose(orbit.get_lines()[0].get_xdata(), d["robot_x1_m"] * 1e6,
                               rtol=1e-9)
    assert "µm" in orbit.get_xlabel() and "E-model at P1" in orbit.get_title()
    time_ax = figures["chatter_time.png"].axes[1]
    np.testing.assert_allclose(time_ax.get_lines()[1].get_ydata(), d["cnc_x2_m"] * 1e6,
                               rtol=1e-9, atol=1e-12)


def test_chatter_map_recommends_no_joint_limit(tmp_path, capsys, demo_robot):
    assert main(["chatter-map", "--n", "13", "-o", str(tmp_path)]) == 0
    best = [s for s in capsys.readouterr().out.splitlines() if s.startswith("best:")]
    d = _csv(tmp_path / "chatter_map.csv")
    lo, hi = np.degrees(demo_robot.lower[1:3]), np.degrees(demo_robot.upper[1:3])
    assert best and d["excluded"].sum() > 0
    for line in best:
        q2, q3 = float(line.split("q2=")[1].split()[0]), float(line.split("q3=")[1].split()[0])
        assert lo[0] + 5 <= q2 <= hi[0] - 5 and lo[1] + 5 <= q3 <= hi[1] - 5
        row = np.argmin(np.hypot(d["q2_deg"] - q2, d["q3_deg"] - q3))
        assert d["excluded"][row] == 0


@pytest.fixture()
def bar_se(tmp_path):
    mesh = tmp_path / "bar.vtu"
    write_volume_mesh(mesh, TetMesh.box((0.4, 0.04, 0.04), (8, 2, 2)))
    out = tmp_path / "bar.h5"
    assert main(["reduce", str(mesh), *IFACES, "--modes", "4", "--backend", "splu",
                 "-o", str(out)]) == 0
    return out


def test_show_writes_mode_shape_vtu(bar_se, tmp_path):
    import meshio

    path = tmp_path / "mode2.vtu"
    assert main(["show", str(bar_se), "--mode", "2", "-o", str(path)]) == 0
    m = meshio.read(path)
    se = formats.read(bar_se)
    q = np.zeros(se.n_dofs)  # the second fixed-interface mode, unit modal mass
    q[se.n_boundary + 1] = 1.0 / np.sqrt(se.M[se.n_boundary + 1, se.n_boundary + 1])
    u = se.expand(q)
    np.testing.assert_allclose(m.points, se.surface_points, atol=1e-12)
    np.testing.assert_allclose(m.point_data["mode_shape"], u[se.surface_nodes],
                               atol=1e-6 * np.abs(u).max())
    assert m.field_data["mode"].tolist() == [2] and m.field_data["freq_hz"][0] == se.freq_hz[1]


def test_mtx_folder_without_extension_is_shown(bar_se, tmp_path, capsys):
    folder = tmp_path / "bar_mtx"
    assert main(["convert", str(bar_se), "-o", str(folder), "--format", "mtx"]) == 0
    assert (folder / "superelement.json").is_file()
    assert main(["show", str(folder)]) == 0
    assert "fixed-interface frequencies [Hz]" in capsys.readouterr().out


def test_convert_round_trips_are_bit_identical(bar_se, tmp_path):
    src = formats.read(bar_se)
    npz = tmp_path / "bar.npz"
    assert main(["convert", str(bar_se), "-o", str(npz)]) == 0
    assert main(["convert", str(npz), "-o", str(tmp_path / "back.h5")]) == 0
    back = formats.read(tmp_path / "back.h5")
    for name in ("K", "M", "T", "surface_points", "freq_hz", "interface_frames"):
        assert np.array_equal(np.asarray(getattr(back, name)), np.asarray(getattr(src, name)))
    for fmt, ext in (("mtx", "mtx"), ("dmig", "bdf")):
        assert main(["convert", str(bar_se), "-o", str(tmp_path / f"b.{ext}")]) == 0
        se = formats.read(tmp_path / f"b.{ext}", fmt)
        np.testing.assert_array_equal(se.K, src.K)
        np.testing.assert_array_equal(se.M, src.M)


def test_bare_flexarm_prints_help_and_succeeds(capsys):
    assert main([]) == 0
    assert capsys.readouterr().out.startswith("usage: flexarm")


def test_verbosity_after_the_command(capsys):
    assert main(["compliance", "--pose", "P1", "-q"]) == 0
    assert main(["-v", "compliance", "--pose", "P1"]) == 0
    assert main(["compliance", "-v", "--pose", "P1"]) == 0
    assert main(["compliance", "-v", "-q"]) == 2  # a usage error: the code, not an exit


def test_help_shows_defaults(capsys):
    with pytest.raises(SystemExit):
        main(["frf", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "highest frequency [Hz] (default: 100.0)" in text
    assert "(default: surface)" in text or "CAD surfaces (default)" in text
    with pytest.raises(SystemExit):
        main(["reduce", "--help"])
    assert "(default: 20)" in " ".join(capsys.readouterr().out.split())


def test_bad_pose_fails_before_building_the_flexible_arm(capsys, monkeypatch):
    _forbid_builds(monkeypatch, "the links were built before the pose was checked")
    assert main(["modes", "--model", "cb", "--pose", "NOPE"]) == 2
    assert "pose must be one of" in capsys.readouterr().err


@pytest.mark.parametrize("argv", [["compare-models", "--poses", "P1,NOPE", "--no-full-fe"],
                                  ["map", "--model", "cb", "--n", "1"],
                                  ["chatter-map", "--model", "cb", "--n", "1"],
                                  ["chatter", "--model", "cb", "--pose", "1,2"],
                                  ["show-arm", "--pose", "NOPE"]])
def test_arguments_are_checked_before_the_links_are_built(argv, capsys, monkeypatch, tmp_path):
    _forbid_builds(monkeypatch, "the links were built before the arguments were checked")
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"flexarm {argv[0]}: error: --")


#: Modules that bind ``build_robot`` by name at import.
_BUILDERS = ("flexarm.assembly.build", "flexarm.assembly", "flexarm.assembly.arm",
             "flexarm.assembly.full_arm", "flexarm.assembly.flexible",
             "flexarm.studies.arm_study", "flexarm.studies.compare_models")


def _forbid_builds(monkeypatch, message: str) -> None:
    """Every ``build_robot`` raises: imported first, so that no module first imported
    while the patch is on keeps the stand-in after the test."""
    import importlib

    def no_build(*args, **kwargs):
        raise AssertionError(message)

    modules = [importlib.import_module(name) for name in _BUILDERS]  # all before any patch
    for module in modules:
        monkeypatch.setattr(module, "build_robot", no_build)


def test_progress_writes_plain_lines_to_a_log(capsys):
    from flexarm.cli._common import Progress

    with Progress("work") as pr:
        pr.note("step 1")
    err = capsys.readouterr().err
    assert "\r" not in err and err.splitlines()[0] == "work ..."
    assert err.splitlines()[1] == "  step 1" and err.splitlines()[2].startswith("work: done in")


def test_progress_on_a_terminal_redraws_one_line_then_ends_plainly(monkeypatch):
    import io
    import sys

    from flexarm.cli._common import Progress

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    term = Terminal()
    monkeypatch.setattr(sys, "stderr", term)
    with Progress("work") as pr:
        time.sleep(1.3)  # one tick of the timer
        pr.note("step 1")
    text = term.getvalue()
    assert "\r" in text and "work ... 00:01" in text  # tqdm's elapsed time, redrawn
    assert "  step 1\n" in text
    assert text.rstrip("\n").split("\n")[-1].split("\r")[-1].startswith("work: done in")


@pytest.mark.parametrize("command", ["modes", "compliance", "frf", "map", "chatter",
                                     "chatter-map", "circle", "show-arm"])
def test_mass_defaults_to_the_cad_surfaces(command):
    from flexarm.cli import parser

    sub = next(a for a in parser()._subparsers._group_actions
               if a.dest == "command").choices[command]
    assert sub.parse_args([]).mass == "surface"


def test_flexible_map_writes_its_ratio_to_the_emodel(tmp_path, figures, capsys, flex_arm):
    flex = ["--model", "cb", "--mesh-size", "0.06", "--modes", "10"]
    assert main(["map", *flex, "--n", "8", "--no-frequencies", "-o", str(tmp_path)]) == 0
    assert main(["map", "--n", "8", "--no-frequencies", "-o", str(tmp_path / "e")]) == 0
    cb, em, ratio = (_csv(p) for p in (tmp_path / "map.csv", tmp_path / "e" / "map.csv",
                                       tmp_path / "map_ratio.csv"))
    np.testing.assert_allclose(ratio["kyy_ratio"], cb["kyy_N_per_mm"] / em["kyy_N_per_mm"],
                               rtol=1e-8)
    assert 0.3 < np.median(ratio["kyy_ratio"]) < 1.0  # flexible links soften the arm
    ax = figures["map_ratio_Kyy_heat.png"].axes[0]
    assert ax.get_title() == "CB Kyy / E-model Kyy over (q2, q3) at P1"
    sing = (ratio["near_singular"] == 1) | (ratio["collides"] == 1)
    np.testing.assert_allclose(ax.collections[0].get_array().compressed(),
                               ratio["kyy_ratio"][~sing], rtol=1e-9)
