from flexarm.cli import main


def test_compliance_table(capsys):
    assert main(["compliance", "--mass", "surface", "--pose", "P1"]) == 0
    out = capsys.readouterr().out
    assert "least stiff direction: y" in out and "eq. 3.12" in out


def test_modes_frf_map_write_pngs(tmp_path, capsys):
    pose = ["--pose", "0,30,10,0,20,0"]
    assert main(["modes", "--mass", "surface", *pose, "-o", str(tmp_path)]) == 0
    assert main(["frf", "--mass", "surface", "--pose", "P2", "-o", str(tmp_path)]) == 0
    assert main(["map", "--mass", "surface", "--n", "12", "-o", str(tmp_path)]) == 0
    names = {p.name for p in tmp_path.iterdir()}
    assert {"mode_energy.png", "frf_bode.png", "map.csv", "map_Kyy_heat.png",
            "map_f1_surface.png"} <= names
    assert len((tmp_path / "map.csv").read_text().splitlines()) == 1 + 12 * 12


def test_bad_pose_is_one_line_error(capsys):
    assert main(["compliance", "--mass", "surface", "--pose", "P9"]) == 2
    assert "pose must be one of" in capsys.readouterr().err
