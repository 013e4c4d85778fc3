"""KRL programs over several files of a folder: calls to other modules are followed and
their moves inlined in call order (each keeping its file and line), the system variables
flow through calls, names of other ``.dat`` files stay apart, and a routine found nowhere,
a recursion or a call with arguments is one line naming the ``.src`` and line."""

from pathlib import Path

import pytest

from flexarm.fe.errors import ReadError
from flexarm.robot.formats.krl_read import read_krl

TOOL = "{X 0.0,Y 0.0,Z 150.0,A 0.0,B 0.0,C 0.0}"


def pos(x, y=0.0, z=600.0):
    return f"{{X {x!r},Y {y!r},Z {z!r},A 180.0,B 0.0,C 180.0}}"


def write(folder: Path, name: str, src: list[str], dat: list[str] | None = None) -> Path:
    """``name.src`` (and ``name.dat`` when ``dat`` is given) in ``folder``."""
    (folder / f"{name}.src").write_text("\n".join([*src, ""]))
    if dat is not None:
        (folder / f"{name}.dat").write_text("\n".join([f"DEFDAT {name}", *dat, "ENDDAT", ""]))
    return folder / f"{name}.src"


def split_program(folder: Path) -> Path:
    """main.src moves, calls approach( ) (the module approach.src) and retract( ) (a GLOBAL
    DEF of lib.src, which has no .dat)."""
    write(folder, "approach", ["&ACCESS RVP", "DEF approach( )", "$VEL.CP = 0.1",
                               "LIN p1 C_DIS", "LIN p2", "END"],
          ["DECL E6POS p1=" + pos(1150.0), "DECL E6POS p2=" + pos(1200.0),
           "DECL GLOBAL E6POS xsafe=" + pos(1100.0, z=700.0)])
    write(folder, "lib", ["DEF lib( )", "END", "GLOBAL DEF retract( )", "LIN xsafe", "END"])
    return write(folder, "main", [
        "DEF main( )", "BAS (#INITMOV,0 )", f"$TOOL = {TOOL}", "$VEL.CP = 0.2", "PTP p0",
        "approach( )", "LIN p3", "retract( )", "END"],
        ["DECL E6POS p0=" + pos(1100.0), "DECL E6POS p3=" + pos(1250.0)])


def test_calls_to_other_modules_are_inlined_in_call_order(tmp_path):
    src = split_program(tmp_path)
    prog = read_krl(src)
    (moves,) = prog.routines.values()  # the main routine moves: one procedure
    assert list(prog.routines) == ["main"] and prog.calls == ("approach", "retract")
    assert [m.targets[0] for m in moves] == ["p0", "p1", "p2", "p3", "xsafe"]
    assert [(Path(m.file).name, m.line) for m in moves] == [
        ("main.src", 5), ("approach.src", 4), ("approach.src", 5), ("main.src", 7),
        ("lib.src", 4)]
    # the called routine sees the caller's tool; its speed stays set after the return
    assert all(m.settings["$TOOL"]["Z"] == 150.0 for m in moves)
    assert [m.settings["$VEL.CP"] for m in moves] == [0.2, 0.1, 0.1, 0.1, 0.1]
    assert prog.main_settings["$VEL.CP"] == 0.2  # the main routine's own
    assert prog.pose("xsafe")[0].tolist() == [1100.0, 0.0, 700.0]  # a GLOBAL of approach.dat
    assert [Path(f).name for f in prog.files] == ["main.src", "approach.src", "lib.src"]


def test_the_same_program_in_one_file_reads_the_same_moves(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    split = read_krl(split_program(tmp_path / "a"))
    one = read_krl(write(tmp_path / "b", "main", [
        "DEF main( )", "BAS (#INITMOV,0 )", f"$TOOL = {TOOL}", "$VEL.CP = 0.2", "PTP p0",
        "approach( )", "LIN p3", "retract( )", "END", "DEF approach( )", "$VEL.CP = 0.1",
        "LIN p1 C_DIS", "LIN p2", "END", "DEF retract( )", "LIN xsafe", "END"],
        ["DECL E6POS p0=" + pos(1100.0), "DECL E6POS p3=" + pos(1250.0),
         "DECL E6POS p1=" + pos(1150.0), "DECL E6POS p2=" + pos(1200.0),
         "DECL E6POS xsafe=" + pos(1100.0, z=700.0)]))
    a, b = split.routines["main"], one.routines["main"]
    assert [(m.kind, m.targets, m.approx, m.settings) for m in a] == \
        [(m.kind, m.targets, m.approx, m.settings) for m in b]
    assert all(split.data[t] == one.data[t] for m in a for t in m.targets)


def test_a_main_routine_that_only_calls_gives_one_procedure_per_called_routine(tmp_path):
    write(tmp_path, "cut_a", ["DEF cut_a( )", "LIN p", "END"], ["DECL E6POS p=" + pos(1100.0)])
    write(tmp_path, "cut_b", ["DEF cut_b( )", "LIN p", "LIN q", "END"],
          ["DECL E6POS p=" + pos(1300.0), "DECL E6POS q=" + pos(1300.0, 50.0)])
    src = write(tmp_path, "cell", ["DEF cell( )", "$VEL.CP = 0.05", "cut_a( )", "cut_b( )",
                                   "END", "DEF spare( )", "LIN p", "END"],
                ["DECL E6POS p=" + pos(1200.0)])
    prog = read_krl(src)
    assert list(prog.routines) == ["cut_a", "cut_b", "spare"]  # spare: nothing calls it
    # each module's p is its own point: the names of other .dat files stay apart
    names = [[m.targets[0] for m in prog.routines[r]] for r in prog.routines]
    assert names == [["cut_a_p"], ["cut_b_p", "q"], ["p"]]
    assert [prog.pose(n[0])[0][0] for n in names] == [1100.0, 1300.0, 1200.0]
    assert all(m.settings["$VEL.CP"] == 0.05 for r in prog.routines.values() for m in r)


def _refused(src: Path, line: int, message: str, at: Path | None = None) -> str:
    """The one line reading ``src`` gives: on ``line`` of ``at`` (default ``src``)."""
    with pytest.raises(ReadError) as info:
        read_krl(src)
    text = str(info.value)
    assert "\n" not in text and text.startswith(f"{at or src}, line {line}: "), text
    assert message in text, text
    return text


def test_a_routine_found_nowhere_names_the_call(tmp_path):
    src = write(tmp_path, "main", ["DEF main( )", "PTP p", "my_sub( )", "END"],
                ["DECL E6POS p=" + pos(1100.0)])
    _refused(src, 3, "my_sub( ) is not a DEF of main.src, nor a module my_sub.src or a "
                     "GLOBAL DEF in its folder")
    write(tmp_path, "lib", ["DEF lib( )", "END", "DEF my_sub( )", "END"])
    _refused(src, 3, "my_sub( ) is a local DEF of lib.src")
    write(tmp_path, "other", ["GLOBAL DEF my_sub( )", "END"])
    write(tmp_path, "more", ["GLOBAL DEF my_sub( )", "END"])
    _refused(src, 3, "my_sub( ) is a GLOBAL DEF of both")


def test_a_recursion_across_files_names_the_call_that_closes_it(tmp_path):
    write(tmp_path, "a", ["DEF a( )", "LIN {X 1100.0,Y 0.0,Z 600.0,A 0,B 0,C 0}", "b( )",
                          "END"])
    write(tmp_path, "b", ["DEF b( )", "", "a( )", "END"])
    src = write(tmp_path, "main", ["DEF main( )", "a( )", "END"], [])
    text = _refused(src, 3, "a( ) is called again while it runs", at=tmp_path / "b.src")
    assert "(main.src:main -> a.src:a -> b.src:b -> a.src:a)" not in text
    assert "(a.src:a -> b.src:b -> a.src:a)" in text and "recursion" in text
    src.write_text("DEF main( )\nPTP {X 1100.0,Y 0.0,Z 600.0,A 0,B 0,C 0}\nmain( )\nEND\n")
    _refused(src, 3, "main( ) is called again while it runs (main.src:main -> main.src:main)")


def test_calls_with_arguments_and_routines_with_parameters_are_refused(tmp_path):
    src = write(tmp_path, "main", ["DEF main( )", "my_sub(p, 3)", "END"],
                ["DECL E6POS p=" + pos(1100.0)])
    _refused(src, 2, "the call 'my_sub(p, 3)' passes arguments")
    src.write_text("DEF main( )\nEND\nDEF my_sub(t:IN)\nEND\n")
    _refused(src, 3, "DEF my_sub takes parameters")


def test_a_target_of_another_module_is_looked_up_in_its_own_dat(tmp_path):
    write(tmp_path, "sub", ["DEF sub( )", "LIN p0", "END"], [])
    src = write(tmp_path, "main", ["DEF main( )", "PTP p0", "sub( )", "END"],
                ["DECL E6POS p0=" + pos(1100.0)])  # local to main.dat: sub does not see it
    _refused(src, 2, "target 'p0' is not declared in sub.dat", at=tmp_path / "sub.src")
    (tmp_path / "main.dat").write_text(f"DEFDAT main PUBLIC\nDECL GLOBAL E6POS p0={pos(1.0)}\n"
                                       "ENDDAT\n")
    prog = read_krl(src)
    assert [m.targets[0] for m in prog.routines["main"]] == ["p0", "p0"]
