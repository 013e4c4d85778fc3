import numpy as np
import pytest

from flexarm.robot.formats.rapid import read_rapid
from flexarm.studies.compensation.program.rapid_out import (
    read_module_text,
    rewrite_targets,
    robtarget_spans,
    write_module_text,
    written_pose,
)

from ..conftest import THESIS

TEXT = """MODULE M(SYSMODULE)
    ! CONST robtarget c1:=[[9,9,9],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST string s:="robtarget s2:=[[1,1,1]]";
    CONST robtarget p1 := [ [1,2,3] , [1,0,0,0],[0,0,0,0],
                            [9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];  ! two lines
    VAR robtarget p2:=[[4,5,6],[0,0,1,0],[-1,0,-1,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget p3:=Offs(p1,0,0,10);
    PROC main()
        MoveL p1,v100,fine,tool0;
        MoveL p2,v100,z10,tool0;  ! keep me
    ENDPROC
ENDMODULE
"""


def test_spans_skip_comments_strings_and_expressions():
    spans = robtarget_spans(TEXT)
    assert sorted(spans) == ["p1", "p2"]
    (a, b), (c, d) = spans["p1"]
    assert TEXT[a:b] == "[1,2,3]" and TEXT[c:d] == "[1,0,0,0]"


def test_only_the_robtargets_and_the_header_change(tmp_path):
    new = rewrite_targets(TEXT, {"P1": ([1.5, -2.25, 3e-7], [0.6, 0.8, 0, 0])},
                          ["compensated", "by a test"])
    lines = new.splitlines()
    assert lines[:3] == [TEXT.splitlines()[0], "    ! compensated", "    ! by a test"]
    assert "CONST robtarget p1 := [ [1.5,-2.25,0] , [0.6,0.8,0,0],[0,0,0,0]," in new
    old_rest = [x for x in TEXT.splitlines() if "p1 :=" not in x]
    new_rest = [x for x in lines[3:] if "p1 :=" not in x]
    assert new_rest == old_rest[1:]
    path = tmp_path / "m.mod"
    write_module_text(path, new)
    back = read_rapid(path)
    assert back.targets["p1"].pos_mm.tolist() == [1.5, -2.25, 0.0]
    assert back.targets["p2"].conf.tolist() == [-1, 0, -1, 1]
    with pytest.raises(ValueError, match="'p3' is not declared with a literal"):
        rewrite_targets(TEXT, {"p3": ([0, 0, 0], [1, 0, 0, 0])})


def test_written_values_read_back_exactly(tmp_path):
    rng = np.random.default_rng(0)
    text, _ = read_module_text(THESIS)
    names = list(read_rapid(THESIS).targets)
    new = {}
    for n in names:
        q = rng.standard_normal(4)
        new[n] = written_pose(rng.uniform(-2000, 2000, 3), q / np.linalg.norm(q))
    path = tmp_path / "t.mod"
    write_module_text(path, rewrite_targets(text, new))
    back = read_rapid(path)
    for n in names:
        assert np.array_equal(back.targets[n].pos_mm, new[n][0])
        assert np.array_equal(back.targets[n].quat, new[n][1])


def test_the_source_encoding_is_kept(tmp_path):
    src = tmp_path / "latin.mod"
    src.write_bytes(TEXT.replace("keep me", "Größe").encode("latin-1"))
    text, enc = read_module_text(src)
    assert enc == "latin-1" and "Größe" in text
    out = write_module_text(tmp_path / "o.mod", rewrite_targets(text, {}, ["x"]), enc)
    assert "Größe".encode("latin-1") in out.read_bytes()
