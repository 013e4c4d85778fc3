import numpy as np
import pytest

from flexarm.cli import main
from flexarm.fe import TetMesh
from flexarm.meshes import write_volume_mesh
from flexarm.reduction import formats

IFACES = ["--interface", "a:0,0.02,0.02,1,0,0,0.04,1e-6",
          "--interface", "b:0.4,0.02,0.02,1,0,0,0.04,1e-6"]


@pytest.fixture()
def part(tmp_path):
    path = tmp_path / "bar.vtu"
    write_volume_mesh(path, TetMesh.box((0.4, 0.04, 0.04), (8, 2, 2)))
    return path


def test_reduce_and_show(part, tmp_path, capsys):
    out = tmp_path / "bar.h5"
    assert main(["reduce", str(part), *IFACES, "--coupling", "rbe3", "--modes", "4",
                 "--backend", "splu", "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "superelement" in text and "fixed-interface freq [Hz]" in text and "wrote" in text
    se = formats.read(out)
    assert se.n_dofs == 16 and se.coupling == "rbe3" and se.interface_names == ("a", "b")
    assert main(["show", str(out)]) == 0
    assert "fixed-interface frequencies [Hz]" in capsys.readouterr().out


@pytest.mark.parametrize("fmt,ext", [("dmig", "bdf"), ("mtx", "mtx"), ("npz", "npz")])
def test_reduce_exports(part, tmp_path, fmt, ext):
    out = tmp_path / f"bar.{ext}"
    assert main(["reduce", str(part), *IFACES, "--method", "guyan", "--backend", "splu",
                 "-o", str(out), "--format", fmt]) == 0
    assert formats.read(out).n_dofs == 12


def test_reduce_writes_op4(part, tmp_path):
    """``--format op4`` on reduce and convert: the superelement's K and M, symmetric."""
    op4 = pytest.importorskip("pyNastran.op4.op4", reason="pyNastran reads OP4 independently")
    ref = tmp_path / "bar.h5"
    args = [str(part), *IFACES, "--method", "guyan", "--backend", "splu"]
    assert main(["reduce", *args, "-o", str(ref)]) == 0
    assert main(["reduce", *args, "--format", "op4", "-o", str(tmp_path / "bar.op4")]) == 0
    assert main(["convert", str(ref), "--format", "op4", "-o", str(tmp_path / "c.op4")]) == 0
    se = formats.read(ref)
    for name in ("bar.op4", "c.op4"):
        back = op4.read_op4(str(tmp_path / name), precision="default", debug=False)
        assert back["KAAX"].form == back["MAAX"].form == 6
        assert np.array_equal(back["KAAX"].data, se.K) and np.array_equal(back["MAAX"].data, se.M)


def test_format_choices_are_the_registry():
    from flexarm.cli.part import _SE_FORMATS

    assert _SE_FORMATS == formats.registry.names()


def test_reduce_errors_are_one_line(part, tmp_path, capsys):
    bad = ["--interface", "far:5,5,5,1,0,0,0.01,0.01"]
    assert main(["reduce", str(part), *bad, "-o", str(tmp_path / "x.h5")]) == 2
    err = capsys.readouterr().err
    assert err.splitlines()[-1].startswith("flexarm reduce: error: region 'far' is empty")
    assert "Traceback" not in err
    assert main(["reduce", str(part), "-o", str(tmp_path / "x.h5")]) == 2
    assert "give at least one --interface" in capsys.readouterr().err
    assert main(["reduce", str(part), *IFACES, "-o", str(tmp_path / "x.xyz")]) == 2
    assert "unknown superelement extension" in capsys.readouterr().err


def test_show_needs_mode_for_picture(part, tmp_path, capsys):
    out = tmp_path / "bar.npz"
    main(["reduce", str(part), *IFACES, "--modes", "2", "--backend", "splu", "-o", str(out)])
    assert main(["show", str(out), "-o", str(tmp_path / "m.png")]) == 2
    assert "--mode N is needed" in capsys.readouterr().err


@pytest.mark.render
def test_show_png(part, tmp_path):
    out = tmp_path / "bar.h5"
    main(["reduce", str(part), *IFACES, "--modes", "3", "--backend", "splu", "-o", str(out)])
    assert main(["show", str(out), "--mode", "2", "-o", str(tmp_path / "m2.png")]) == 0
    assert (tmp_path / "m2.png").stat().st_size > 1000


def test_study_part(tmp_path, capsys):
    assert main(["study-part", "--divisions", "6x1x1", "--modes", "0,4",
                 "--representations", "rbe2,k4", "-o", str(tmp_path)]) == 0
    lines = (tmp_path / "study.csv").read_text().splitlines()
    assert lines[0].startswith("mesh,n_full,representation,n_modes") and len(lines) == 5
    assert (tmp_path / "study.png").stat().st_size > 1000


def test_modal_clamp_of_one_line_of_nodes_says_how_many(part, capsys):
    assert main(["modal", str(part), "--fix", "x=min & y=min"]) == 2
    err = capsys.readouterr().err
    assert "--fix 'x=min & y=min': 3 nodes clamped" in err
    assert err.strip().splitlines()[-1].endswith(
        "clamps 3 nodes on one line: the part can still rotate (singular stiffness); "
        "select a face region, e.g. 'x<0.01'")
    assert main(["modal", str(part), "--fix", "x=min & y=min & z=min"]) == 2
    assert "clamps 1 node: the part can still rotate" in capsys.readouterr().err
    assert main(["modal", str(part), "--fix", "x=min", "-n", "2"]) == 0
    assert "--fix 'x=min': 9 nodes clamped" in capsys.readouterr().err
