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


def test_modes_beyond_the_model_say_so_in_one_line(capsys):
    """-n above the arm's number of modes lists them all and says so in one line."""
    from flexarm.assembly.analyses import modes
    from flexarm.assembly.arm import ArmSpec, build_arm
    from flexarm.robot import load_robot

    robot = load_robot()
    n = modes(build_arm(robot, ArmSpec(mass="surface")).model, robot.pose("P1")).freq_hz.size
    assert main(["modes", "--mass", "surface", "--pose", "P1", "-n", "500"]) == 0
    cap = capsys.readouterr()
    rows = [r for r in cap.out.splitlines()[1:] if r.split()[0].isdigit()]
    assert len(rows) == n
    assert cap.err.strip().splitlines() == [
        f"warning: --n-modes 500: the E-model arm has only {n} modes; listing all {n}"]
    assert main(["modes", "--mass", "surface", "--pose", "P1", "-n", "3"]) == 0
    cap = capsys.readouterr()
    assert "warning" not in cap.err and f"... {n - 3} more modes" in cap.out
    assert main(["modes", "--mass", "surface", "--pose", "P1", "-n", "0"]) == 2
    assert capsys.readouterr().err.strip().endswith("-n/--n-modes 0: outside 1..100000")


def test_modes_without_n_warns_of_nothing(capsys):
    """The default count is not the user's: an E-model with fewer modes lists them all
    without a warning."""
    assert main(["modes", "--model", "emodel", "--mass", "surface", "--pose", "P1"]) == 0
    cap = capsys.readouterr()
    rows = [r for r in cap.out.splitlines()[1:] if r.split()[0].isdigit()]
    assert 6 <= len(rows) < 24 and cap.err.strip() == ""
