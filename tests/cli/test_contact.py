from flexarm.cli import main


def test_circle_chatter_and_map_commands(tmp_path, capsys):
    out = tmp_path / "o"
    assert main(["circle", "--mass", "surface", "--proc", "Path_30", "--loads", "0,400",
                 "--step", "10", "-o", str(out)]) == 0
    assert main(["chatter", "--mass", "surface", "--pose", "P1", "--kc", "5e5", "--dir", "30",
                 "--duration", "0.5", "-o", str(out)]) == 0
    assert main(["chatter-map", "--mass", "surface", "--n", "5", "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "conf met at 3/3 targets" in text
    assert "verdict: robot CHATTERS (mode coupling); CNC stable" in text
    assert "weak Y" in text
    for name in ("circle_Path_30.csv", "circle_top.png", "circle_polar.png", "circle_z.png",
                 "chatter_time.png", "chatter_orbit.png", "chatter_map.csv", "chatter_map.png"):
        assert (out / name).stat().st_size > 0


def test_circle_flexible_nonlinear_and_static_overlay(tmp_path, capsys, flex_arm, demo_robot):
    from dataclasses import replace
    from importlib.resources import files

    from flexarm.robot.effects import Effect
    from flexarm.robot.formats import write as write_robot

    toml = tmp_path / "robot.toml"
    write_robot(toml, replace(demo_robot, effects=(Effect("backlash", 2, (("width", 2e-4),)),)))
    example = files("flexarm") / "data" / "examples" / "circle_static_example.csv"
    out = tmp_path / "o"
    assert main(["circle", "--robot", str(toml), "--model", "cb", "--mesh-size", "0.06",
                 "--modes", "10", "--compare-models", "--loads", "0,400,800", "--step", "10",
                 "--measured", str(example), "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "E-model (nonlinear_solver, laws on joints 3)" in text
    assert "CB (nonlinear_solver, laws on joints 3)" in text
    assert "measured: 73 readings at [0.0, 400.0, 800.0] N" in text
    head = (out / "circle_Path_30.csv").read_text().splitlines()[0]
    assert "bar_mm_E-model_800N" in head and "bar_mm_CB_800N" in head
    for name in ("circle_top.png", "circle_polar.png", "circle_z.png"):
        assert (out / name).stat().st_size > 0


def test_circle_prints_the_job_result(tmp_path, capsys, demo_robot):
    from flexarm.studies.contact import run_circle

    out = tmp_path / "o"
    assert main(["circle", "--loads", "0,400", "--step", "10", "--pivot", "1333,48,588",
                 "-o", str(out)]) == 0
    text = capsys.readouterr().out.splitlines()
    res = run_circle(demo_robot, loads=[0.0, 400.0], step=10.0, pivot=[1.333, 0.048, 0.588])
    assert "pivot [1333.0, 48.0, 588.0] mm" in text[0]
    assert text[:-4] == res.text().splitlines()
    assert text[-4:] == [f"wrote {out / n}" for n in ("circle_Path_30.csv", "circle_top.png",
                                                      "circle_polar.png", "circle_z.png")]


def test_chatter_prints_the_job_result(capsys, demo_robot):
    from flexarm.assembly import emodel
    from flexarm.studies.contact import run_chatter

    assert main(["chatter", "--pose", "P1", "--kc", "3e5", "--normal", "10",
                 "--duration", "0.05"]) == 0
    st = run_chatter(emodel(demo_robot), demo_robot.pose("P1"), 3e5, 30.0, 10.0,
                     duration=0.05)
    assert capsys.readouterr().out == st.text() + "\n"


def test_bad_circle_options_are_one_line_errors(capsys):
    assert main(["circle", "--loads", "0,lots"]) == 2
    assert "--loads lots: not a number" in capsys.readouterr().err
    assert main(["circle", "--effect", "backlash:j9=1mrad"]) == 2
    assert "joint 9 outside 1..6" in capsys.readouterr().err


def test_circle_unreachable_target_is_one_line_naming_file_target_and_line(tmp_path, capsys):
    """A target moved to 8.8 m: exit 2, one line with the file, procedure, target and line,
    nothing written."""
    from importlib.resources import files

    text = (files("flexarm") / "data" / "rapid" / "ldbb_thesis.mod").read_text()
    far = tmp_path / "far.mod"
    far.write_text(text.replace("Target_50:=[[883.561", "Target_50:=[[8800.0"))
    out = tmp_path / "out"
    rc = main(["circle", "--mass", "surface", "--rapid", str(far), "--proc", "Path_20",
               "--loads", "0,200", "-o", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    line = next(k for k, ln in enumerate(text.splitlines(), start=1)
                if "PROC Path_20" in ln) + 2  # its second motion: MoveL Target_50
    assert rc == 2 and len(err) == 1 and "Traceback" not in err[0]
    assert err[0].startswith(f"flexarm circle: error: {far}: Path_20: MoveL to Target_50 "
                             f"(line {line}): the path leaves the arm's reach")
    assert not out.exists()
