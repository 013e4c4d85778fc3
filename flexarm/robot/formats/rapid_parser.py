"""RAPID statements: the module, its declarations, routines and Move instructions."""

from __future__ import annotations

import logging
from collections import ChainMap
from collections.abc import Iterable
from typing import Any

from .rapid_data import (
    _SIGNATURES,
    SUPPORTED_INSTRUCTIONS,
    Declaration,
    JointTarget,
    Motion,
    Procedure,
    RapidModule,
    RobTarget,
    Target,
)
from .rapid_lexer import _Tok
from .rapid_values import _tuples, _ValueParser

logger = logging.getLogger(__name__)

_N_TARGETS = {"MoveL": 1, "MoveJ": 1, "MoveC": 2, "MoveAbsJ": 1}
_KINDS = {k.lower(): k for k in SUPPORTED_INSTRUCTIONS}
#: instruction -> lower-case optional argument -> its name as RAPID spells it
_OPTIONS = {kind: {k.lower(): k for k in allowed} for kind, (_, allowed) in _SIGNATURES.items()}


class _Parser(_ValueParser):
    """Recursive descent over the token list; ``scope`` maps lower-case names to values."""

    def __init__(self, toks: Iterable[_Tok], file: str, scope: ChainMap | dict[str, Any],
                 ignore: set[str]):
        super().__init__(toks, file, scope)
        self.ignore = ignore

    # -- module
    def module(self) -> RapidModule:
        self.expect("MODULE")
        mod_name = self.name("a module name").text
        if self.peek().text == "(":  # MODULE m(SYSMODULE, NOVIEW)
            while self.next().text != ")":
                if self.peek().kind == "eof":
                    raise self.error("unclosed module attribute list")
        targets: dict[str, RobTarget] = {}
        joint_targets: dict[str, JointTarget] = {}
        data: dict[str, Declaration] = {}
        procs: dict[str, Procedure] = {}
        proc_names: set[str] = set()
        while True:
            tok = self.peek()
            if tok.kind == "eof":
                raise self.error(f"missing ENDMODULE for MODULE {mod_name}")
            word = tok.text.upper() if tok.kind == "name" else ""
            if word == "ENDMODULE":
                self.next()
                if self.peek().kind != "eof":
                    raise self.error(f"unexpected '{self.peek().text}' after ENDMODULE")
                break
            if word in ("LOCAL", "TASK"):
                self.next()
                continue
            if word in ("CONST", "PERS", "VAR"):
                decl = self.declaration()
                key = decl.name.lower()
                if key in self.scope:
                    raise self.error(f"'{decl.name}' is declared twice", decl.line)
                self.scope[key] = decl.value
                if isinstance(decl.value, RobTarget):
                    targets[decl.name] = decl.value
                elif isinstance(decl.value, JointTarget):
                    joint_targets[decl.name] = decl.value
                else:
                    data[decl.name] = decl
            elif word == "PROC":
                proc = self.procedure()
                if proc.name.lower() in proc_names:
                    raise self.error(f"PROC '{proc.name}' is defined twice", proc.line)
                procs[proc.name] = proc
                proc_names.add(proc.name.lower())
            elif word in ("FUNC", "TRAP"):
                self.skip_routine(word)
            else:
                raise self.error(f"unexpected '{tok.text}' at module level (expected a data "
                                 "declaration, PROC or ENDMODULE)")
        return RapidModule(mod_name, targets, procs, joint_targets, data, self.file)

    def skip_routine(self, word: str) -> None:
        start = self.next()
        end = "END" + word
        while not self.is_kw(end):
            if self.peek().kind == "eof":
                raise self.error(f"missing {end} for the {word} on line {start.line}", start.line)
            self.next()
        self.next()
        logger.info("%s, line %d: skipped a %s routine", self.file, start.line, word)

    # -- declarations
    def declaration(self) -> Declaration:
        storage = self.next()
        type_name = self.name("a data type").text
        name_tok = self.name("a data name")
        if self.peek().text == "{":
            raise self.error(f"array declarations are not supported ('{name_tok.text}')")
        value: Any = None
        if self.peek().text == ":=":
            self.next()
            value = self.expression()
        tok = self.next()
        if tok.text != ";":
            raise self.error(f"expected ';' after the declaration of '{name_tok.text}', "
                             f"got '{tok.text or 'end of file'}'", tok.line)
        kind = type_name.lower()
        if value is None and storage.text.upper() != "CONST":
            pass  # VAR/PERS without an initial value: kept as a Declaration, error on use
        elif value is None and kind not in ("robtarget", "jointtarget"):
            raise self.error(f"CONST '{name_tok.text}' has no value", name_tok.line)
        elif kind == "robtarget":
            value = self.robtarget(name_tok.text, value, name_tok.line)
        elif kind == "jointtarget":
            value = self.jointtarget(name_tok.text, value, name_tok.line)
        elif kind == "num" and value is not None and not isinstance(value, float):
            raise self.error(f"num '{name_tok.text}' must be a number", name_tok.line)
        elif isinstance(value, (RobTarget, JointTarget)):
            raise self.error(f"'{name_tok.text}' of type {type_name} cannot hold a target",
                             name_tok.line)
        else:
            value = _tuples(value)
        return Declaration(storage.text.upper(), type_name, name_tok.text, value, name_tok.line)

    # -- procedures
    def procedure(self) -> Procedure:
        start = self.expect("PROC")
        name = self.name("a procedure name").text
        self.expect("(", f" after PROC {name}")
        if self.peek().text != ")":
            raise self.error(f"PROC {name}: procedures with parameters are not supported")
        self.expect(")")
        outer = self.scope
        self.scope = ChainMap({}, outer)  # routine data shadow module data (no copy of it)
        motions: list[Motion] = []
        local: set[str] = set()
        while True:
            tok = self.peek()
            if tok.kind == "eof" or self.is_kw("ENDMODULE", "PROC"):
                raise self.error(f"missing ENDPROC for PROC {name} (line {start.line})")
            word = tok.text.upper() if tok.kind == "name" else ""
            if word == "ENDPROC":
                self.next()
                break
            if word in ("CONST", "PERS", "VAR"):
                decl = self.declaration()
                if decl.name.lower() in local:
                    raise self.error(f"'{decl.name}' is declared twice", decl.line)
                local.add(decl.name.lower())
                self.scope[decl.name.lower()] = decl.value
                continue
            motions.append(self.instruction())
            if motions[-1] is None:
                motions.pop()
        self.scope = outer
        return Procedure(name, tuple(motions), start.line)

    def instruction(self) -> Motion | None:
        tok = self.next()
        if tok.kind != "name":
            raise self.error(f"unexpected '{tok.text}' (expected an instruction)", tok.line)
        if self.peek().text == ":=":
            raise self.error(f"unsupported statement: assignment to '{tok.text}' (supported "
                             f"instructions: {', '.join(SUPPORTED_INSTRUCTIONS)})", tok.line)
        kinds = _KINDS
        if tok.text.lower() in self.ignore:
            while self.next().text != ";":
                if self.peek().kind == "eof":
                    raise self.error(f"missing ';' after {tok.text}", tok.line)
            logger.info("%s, line %d: ignored %s", self.file, tok.line, tok.text)
            return None
        if tok.text.lower() not in kinds:
            raise self.error(f"unsupported instruction '{tok.text}' "
                             f"(supported: {', '.join(SUPPORTED_INSTRUCTIONS)})", tok.line)
        return self.motion(kinds[tok.text.lower()], tok.line)

    def arguments(self, instr: str, line: int) -> tuple[list[list[_Tok]], list[tuple]]:
        """Split ``arg, arg \\Opt:=x, ...;`` into positional token runs and optional args."""
        positional: list[list[_Tok]] = []
        optional: list[tuple[str, list[_Tok] | None, int]] = []
        while True:
            tok = self.peek()
            if tok.text == ";":
                self.next()
                return positional, optional
            if tok.kind == "eof" or self.is_kw("ENDPROC", "ENDMODULE"):
                raise self.error(f"missing ';' at the end of {instr}", line)
            if tok.text == "\\":
                self.next()
                opt = self.name("an optional argument name after '\\'").text
                value = None
                if self.peek().text == ":=":
                    self.next()
                    value = self.run()
                optional.append((opt, value, len(positional) - 1))
            else:
                run = self.run()
                if not run:
                    raise self.error(f"empty argument in {instr}", line)
                _check_commas(self, run)
                positional.append(run)
            if self.peek().text == ",":
                self.next()

    def run(self) -> list[_Tok]:
        """Tokens of one argument: up to ',', '\\' or ';' outside brackets."""
        out: list[_Tok] = []
        depth = 0
        while True:
            tok = self.peek()
            if tok.kind == "eof" or (depth == 0 and tok.text in (",", "\\", ";")):
                return out
            if depth == 0 and self.is_kw("ENDPROC", "ENDMODULE"):
                return out
            depth += tok.text in ("[", "(") and tok.kind == "op"
            depth -= tok.text in ("]", ")") and tok.kind == "op"
            out.append(self.next())

    def evaluate(self, run: list[_Tok]) -> Any:
        sub = _Parser(run + [_Tok("eof", "", run[-1].line)], self.file, self.scope, self.ignore)
        value = sub.expression()
        if sub.peek().kind != "eof":
            raise self.error(f"unexpected '{sub.peek().text}' in an argument", sub.peek().line)
        return value

    def motion(self, kind: str, line: int) -> Motion:
        names, allowed = _SIGNATURES[kind]
        positional, optional = self.arguments(kind, line)
        if len(positional) != len(names):
            raise self.error(f"{kind} expects {len(names)} arguments ({', '.join(names)}), "
                             f"got {len(positional)}", line)
        allowed_l = _OPTIONS[kind]
        wobj = None
        options: list[tuple[str, str | None]] = []
        for opt, value, _after in optional:
            if opt.lower() not in allowed_l:
                raise self.error(f"unknown optional argument '\\{opt}' for {kind} "
                                 f"(allowed: {', '.join(allowed)})", line)
            text = None if value is None else "".join(t.text for t in value)
            if opt.lower() == "wobj":
                wobj = text
            else:
                options.append((allowed_l[opt.lower()], text))
        targets: list[Target] = []
        for k in range(_N_TARGETS[kind]):
            run = positional[k]
            value = self.evaluate(run)
            text = "".join(t.text for t in run)
            if kind == "MoveAbsJ":
                if isinstance(value, list):
                    value = self.jointtarget(text, value, run[0].line)
                if not isinstance(value, JointTarget):
                    raise self.error(f"{kind}: {names[k]} '{text}' is not a jointtarget", line)
            else:
                if isinstance(value, list):
                    value = self.robtarget(text, value, run[0].line)
                if not isinstance(value, RobTarget):
                    raise self.error(f"{kind}: {names[k]} '{text}' is not a robtarget", line)
            targets.append(value)
        speed, zone, tool = ("".join(t.text for t in run) for run in positional[-3:])
        return Motion(kind, tuple(targets), speed, zone, tool, wobj, tuple(options), line)


def _check_commas(parser: _Parser, run: list[_Tok]) -> None:
    """Two operands side by side at bracket depth 0 mean a missing comma."""
    depth = 0
    for prev, tok in zip(run, run[1:], strict=False):
        depth += prev.text in ("[", "(") and prev.kind == "op"
        depth -= prev.text in ("]", ")") and prev.kind == "op"
        ends = prev.kind in ("name", "num", "str") or (prev.kind == "op" and prev.text in "])")
        starts = tok.kind in ("name", "num", "str") or (tok.kind == "op" and tok.text == "[")
        if depth == 0 and ends and starts:
            raise parser.error(f"expected ',' between '{prev.text}' and '{tok.text}'", tok.line)
