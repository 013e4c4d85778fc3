"""RAPID values: expressions, aggregates, ``Offs``/``RelTool`` and target literals.

:class:`_ValueParser` evaluates the expressions RAPID data and Move arguments are
written with (numbers, strings, ``TRUE``/``FALSE``, ``[...]`` aggregates, data names,
``+ - * /``, ``Offs`` and ``RelTool``) and checks robtarget/jointtarget literals.  The
small helpers at the end format values back to RAPID text.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from typing import Any

import numpy as np

from ..quaternions import quat_from_intrinsic_xyz, quat_multiply, quat_to_matrix
from ..tolerances import tol
from .rapid_data import EXTAX_UNUSED, JointTarget, RobTarget
from .rapid_lexer import _Tok, _TokenStream

_FUNCTIONS = ("Offs", "RelTool")
_ROBTARGET_FORM = "[[x,y,z],[q1,q2,q3,q4],[cf1,cf4,cf6,cfx],[eax_a,...,eax_f]]"
_JOINTTARGET_FORM = "[[rax_1,...,rax_6],[eax_a,...,eax_f]]"


class _ValueParser(_TokenStream):
    """Expression evaluation; ``scope`` maps lower-case data names to their values."""

    def __init__(self, toks: Iterable[_Tok], file: str, scope: Mapping[str, Any]):
        super().__init__(toks, file)
        self.scope = scope
        self.depth = 0  # brackets open around the current factor

    def robtarget(self, name: str, value: Any, line: int) -> RobTarget:
        if isinstance(value, RobTarget):
            return value.renamed(name)
        if value is None:
            raise self.error(f"robtarget '{name}' has no value (expected := {_ROBTARGET_FORM})",
                             line)
        shape = _shape(value)
        if shape != [3, 4, 4, 6] or not _all_numbers(value):
            raise self.error(f"malformed robtarget '{name}': expected {_ROBTARGET_FORM}, "
                             f"got {_describe(value)}", line)
        pos, quat, conf, extax = (np.asarray(v, dtype=np.float64) for v in value)
        if np.any(conf != np.round(conf)):
            raise self.error(f"malformed robtarget '{name}': configuration data "
                             f"{_fmt_list(conf)} must be integers", line)
        norm = float(np.linalg.norm(quat))
        if abs(norm - 1.0) > tol.quaternion_norm:
            raise self.error(f"malformed robtarget '{name}': orientation {_fmt_list(quat)} is not "
                             f"a unit quaternion (|q| = {norm:.6g})", line)
        return RobTarget(name, pos, quat, conf.astype(np.int64), extax)

    def jointtarget(self, name: str, value: Any, line: int) -> JointTarget:
        if isinstance(value, JointTarget):
            return JointTarget(name, value.joints_deg, value.extax)
        if value is None or _shape(value) != [6, 6] or not _all_numbers(value):
            raise self.error(f"malformed jointtarget '{name}': expected {_JOINTTARGET_FORM}, "
                             f"got {_describe(value)}", line)
        return JointTarget(name, value[0], value[1])

    # -- expressions: numbers, strings, TRUE/FALSE, aggregates, data names, Offs, RelTool
    def expression(self) -> Any:
        return self._left_to_right(self.term, ("+", "-"))

    def term(self) -> Any:
        return self._left_to_right(self.factor, ("*", "/"))

    def _left_to_right(self, operand: Callable[[], Any], ops: tuple[str, ...]) -> Any:
        """``operand (op operand)*`` with ``op`` in ``ops``, evaluated left to right."""
        value = operand()
        while self.peek().text in ops:
            op = self.next()
            value = self.arith(op, value, operand())
        return value

    def arith(self, op: _Tok, a: Any, b: Any) -> float:
        if not (isinstance(a, float) and isinstance(b, float)):
            raise self.error(f"'{op.text}' is only supported between numbers", op.line)
        if op.text == "+":
            return a + b
        if op.text == "-":
            return a - b
        if op.text == "*":
            return a * b
        if b == 0.0:
            raise self.error("division by zero", op.line)
        return a / b

    def factor(self) -> Any:
        signs = []  # unary signs, read in a loop: a chain of them is no recursion
        while self.peek().text in ("-", "+") and self.peek().kind == "op":
            signs.append(self.next())
        value = self._operand()
        for tok in reversed(signs):
            if not isinstance(value, float):
                raise self.error(f"unary '{tok.text}' needs a number", tok.line)
            value = -value if tok.text == "-" else value
        return value

    def _operand(self) -> Any:
        tok = self.next()
        if tok.kind == "num":
            return float(tok.text)
        if tok.kind == "str":
            return tok.text[1:-1].replace('""', '"')
        if tok.text in ("(", "[") and tok.kind == "op":
            self.depth += 1
            if self.depth > tol.rapid_max_nesting:  # RAPID data nest 3 deep at most
                raise self.error(f"brackets nested more than {tol.rapid_max_nesting} deep "
                                 "(RAPID aggregates nest a few levels)", tok.line)
            if tok.text == "(":
                value = self.expression()
                self.expect(")")
            else:
                value = [self.expression()]
                while self.peek().text == ",":
                    self.next()
                    value.append(self.expression())
                self.expect("]", " to close the aggregate")
            self.depth -= 1
            return value
        if tok.kind == "name":
            upper = tok.text.upper()
            if upper in ("TRUE", "FALSE"):
                return upper == "TRUE"
            if self.peek().text == "(":
                return self.call(tok)
            key = tok.text.lower()
            if key not in self.scope:
                raise self.error(f"unknown data '{tok.text}'", tok.line)
            if self.scope[key] is None:
                raise self.error(f"'{tok.text}' is declared without a value", tok.line)
            return self.scope[key]
        raise self.error(f"unexpected '{tok.text or 'end of file'}' in an expression", tok.line)

    def call(self, func: _Tok) -> RobTarget:
        names = {f.lower(): f for f in _FUNCTIONS}
        if func.text.lower() not in names:
            raise self.error(f"unsupported function '{func.text}' "
                             f"(supported: {', '.join(_FUNCTIONS)})", func.line)
        fname = names[func.text.lower()]
        self.expect("(")
        self.depth += 1
        if self.depth > tol.rapid_max_nesting:
            raise self.error(f"calls nested more than {tol.rapid_max_nesting} deep", func.line)
        self.record()
        args = [self.expression()]
        opts: dict[str, float] = {}
        while self.peek().text in (",", "\\"):
            if self.next().text == "\\":
                opt = self.name("an optional argument name").text
                self.expect(":=")
                opts[opt.lower()] = self.expression()
            else:
                args.append(self.expression())
        text = " ".join(t.text for t in self.recorded())
        self.expect(")", f" to close {fname}(")
        self.depth -= 1
        if (len(args) != 4 or not isinstance(args[0], RobTarget)
                or not all(isinstance(a, float) for a in args[1:])):
            raise self.error(f"{fname} expects (robtarget, dx, dy, dz)", func.line)
        allowed = {"rx", "ry", "rz"} if fname == "RelTool" else set()
        bad = sorted(set(opts) - allowed)
        if bad or not all(isinstance(v, float) for v in opts.values()):
            raise self.error(f"unsupported optional argument '\\{bad[0] if bad else ''}' "
                             f"of {fname}", func.line)
        p: RobTarget = args[0]
        d = np.array(args[1:], dtype=np.float64)
        if fname == "Offs":
            return RobTarget(f"Offs({text})", p.pos_mm + d, p.quat, p.conf, p.extax)
        pos = p.pos_mm + quat_to_matrix(p.quat) @ d
        turn = quat_from_intrinsic_xyz([opts.get(a, 0.0) for a in ("rx", "ry", "rz")])
        return RobTarget(f"RelTool({text})", pos, quat_multiply(p.quat, turn), p.conf, p.extax)


def _tuples(value: Any) -> Any:
    return tuple(_tuples(v) for v in value) if isinstance(value, list) else value


def _shape(value: Any) -> list[int] | None:
    if not isinstance(value, list) or not all(isinstance(v, list) for v in value):
        return None
    return [len(v) for v in value]


def _all_numbers(value: list) -> bool:
    return all(isinstance(x, float) for v in value for x in v)


def _fmt_list(a: np.ndarray) -> str:
    return "[" + ",".join(_num(x) for x in a) + "]"


def _describe(value: Any) -> str:
    if value is None:
        return "no value"
    if isinstance(value, list):
        return "[" + ",".join(_describe(v) if isinstance(v, list) else
                              (_num(v) if isinstance(v, float) else repr(v)) for v in value) + "]"
    return repr(value)


def _num(x: float) -> str:
    """RAPID literal of a number that reads back to the same float."""
    x = float(x)
    if x == EXTAX_UNUSED:
        return "9E+09"
    if x.is_integer() and abs(x) < 1e15:
        return str(int(x))
    return repr(x)
