"""The robot TOML's ``[modal_damping]`` table: written, read back, bad input refused."""

from __future__ import annotations

from dataclasses import replace

import pytest

from flexarm.fe.errors import ReadError
from flexarm.robot.demo_arm import load_demo_robot
from flexarm.robot.formats import read, write

TABLE = {"P1": ((7.61, 16.5, 39.9), (0.021, 0.018, 0.0305)), "P3": ((9.4,), (0.02,))}


def test_modal_damping_round_trips(tmp_path):
    robot = replace(load_demo_robot(), modal_damping=TABLE)
    path = write(tmp_path / "r.toml", robot)
    text = path.read_text()
    assert "[modal_damping.P1]" in text and "zeta = [0.021, 0.018, 0.0305]" in text
    back = read(path)
    assert back.modal_damping == TABLE
    assert read(write(tmp_path / "plain.toml", load_demo_robot())).modal_damping == {}
    assert "modal_damping" not in (tmp_path / "plain.toml").read_text()


@pytest.mark.parametrize("table, message", [
    ('[modal_damping.P9]\nfreq_hz = [8.0]\nzeta = [0.02]', "modal_damping.P9: no pose 'P9'"),
    ('[modal_damping.P1]\nfreq_hz = [8.0, 9.0]\nzeta = [0.02]',
     "modal_damping.P1: 2 freq_hz but 1 zeta"),
    ('[modal_damping.P1]\nfreq_hz = [8.0]\nzeta = [1.5]',
     r"modal_damping.P1.zeta must lie in \[0, 1\)"),
    ('[modal_damping.P1]\nfreq_hz = [8.0]\nzetta = [0.02]',
     "modal_damping.P1: unknown key 'zetta' \\(did you mean 'zeta'\\?\\)"),
    ('[modal_damping.P1]\nfreq_hz = [8.0]', "modal_damping.P1: missing 'zeta'"),
    ('[modal_damping.P1]\nfreq_hz = 8.0\nzeta = [0.02]',
     "modal_damping.P1.freq_hz must be a list of numbers"),
])
def test_bad_tables_name_the_key(tmp_path, table, message):
    path = write(tmp_path / "r.toml", load_demo_robot())
    path.write_text(path.read_text() + "\n" + table + "\n")
    with pytest.raises(ReadError, match=message):
        read(path)
