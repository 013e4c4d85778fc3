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
