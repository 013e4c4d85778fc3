"""FormatRegistry: lookup by extension or name, later registrations win, extensions by mode,
options passed through, and a reader's failure wrapped in one ReadError (FlexarmError kept)."""

from __future__ import annotations

import pytest

from flexarm.fe.errors import MeshError, ReadError
from flexarm.fe.formats import FileFormat, FormatRegistry


def _text_registry():
    reg = FormatRegistry("note")
    reg.register("text", (".txt",), read=lambda p, **kw: (p.read_text(), kw),
                 write=lambda p, obj, **kw: p.write_text(obj + kw.get("end", "")))
    reg.register("log", (".LOG",), read=lambda p: p.read_text())
    reg.register("dump", (".dump",), write=lambda p, obj: p.write_text(obj))
    return reg


def test_names_and_extensions_by_mode():
    reg = _text_registry()
    assert reg.names() == ("text", "log", "dump")
    assert reg.extensions() == (".dump", ".log", ".txt")
    assert reg.extensions("r") == (".log", ".txt")
    assert reg.extensions("w") == (".dump", ".txt")
    assert reg.find("A/B.Log").name == "log" and reg.find("noext") is None


def test_later_registration_wins():
    reg = _text_registry()
    fmt = reg.register("markdown", (".txt", ".md"), read=lambda p: "md")
    assert isinstance(fmt, FileFormat) and fmt.extensions == (".txt", ".md")
    assert reg.find("a.txt") is fmt
    assert reg.format_of("a.log", name="text").name == "text"  # still reachable by name


def test_explicit_name_overrides_the_extension(tmp_path):
    reg = _text_registry()
    path = tmp_path / "notes.log"
    assert reg.write(path, "hello", name="text", end="!") == path
    assert path.read_text() == "hello!"
    assert reg.read(path, name="text", flag=3) == ("hello!", {"flag": 3})
    assert reg.read(str(path)) == "hello!"


def test_mode_errors_name_the_format():
    reg = _text_registry()
    with pytest.raises(ValueError, match=r"a\.dump: cannot read note files of format dump "
                                         r"\(can read: \.log, \.txt\)"):
        reg.format_of("a.dump", mode="r")
    with pytest.raises(ValueError, match=r"unknown note extension '\(none\)'"):
        reg.format_of("README")


def test_reader_failure_becomes_one_read_error(tmp_path):
    def broken(path):
        raise KeyError("section")

    def bad_mesh(path):
        raise MeshError("part: 1 inverted tetrahedra")

    reg = FormatRegistry("note")
    reg.register("broken", (".brk",), read=broken)
    reg.register("mesh", (".msh",), read=bad_mesh)
    (tmp_path / "a.brk").write_text("")
    (tmp_path / "a.msh").write_text("")
    with pytest.raises(ReadError, match=r"a\.brk: cannot read it as a broken note "
                                        r"\('section'\)$") as info:
        reg.read(tmp_path / "a.brk")
    assert isinstance(info.value.__cause__, KeyError)
    with pytest.raises(MeshError, match="^part: 1 inverted tetrahedra$"):
        reg.read(tmp_path / "a.msh")  # flexarm errors pass unchanged
