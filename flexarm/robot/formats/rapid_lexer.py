"""RAPID tokens: the lexer and the token cursor the parser is built on.

``!`` comments, whitespace and the old ``%%% VERSION ... %%%`` header are dropped;
every token keeps its 1-based line so errors can name it.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from ...fe.errors import ReadError


@dataclass(frozen=True)
class _Tok:
    kind: str  # "name", "num", "str", "op", "eof"
    text: str
    line: int


_TOKEN_RE = re.compile(
    r"(?P<ws>[ \t\r\f\v]+)|(?P<nl>\n)|(?P<comment>![^\n]*)"
    r"|(?P<str>\"(?:[^\"\n]|\"\")*\")"
    r"|(?P<num>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)"
    r"|(?P<name>[A-Za-z_][A-Za-z0-9_]*)"
    r"|(?P<op>:=|<>|<=|>=|[\[\](){},;:\\+\-*/=<>])"
)
_HEADER_RE = re.compile(r"\s*%%%.*?%%%", re.DOTALL)  # old "%%% VERSION:1 ... %%%" header


def _tokenize(text: str, file: str) -> list[_Tok]:
    toks: list[_Tok] = []
    line = 1
    pos = 0
    header = _HEADER_RE.match(text)
    if header:
        line += header.group(0).count("\n")
        pos = header.end()
    while pos < len(text):
        m = _TOKEN_RE.match(text, pos)
        if m is None:
            raise ReadError(f"{file}, line {line}: unexpected character {text[pos]!r}")
        kind = m.lastgroup
        if kind == "nl":
            line += 1
        elif kind in ("str", "num", "name", "op"):
            toks.append(_Tok(kind, m.group(0), line))
        pos = m.end()
    toks.append(_Tok("eof", "", toks[-1].line if toks else line))  # errors at end of text
    return toks


class _TokenStream:
    """Cursor over a token list with the look-ahead and error helpers of the parser."""

    def __init__(self, toks: list[_Tok], file: str):
        self.toks = toks
        self.i = 0
        self.file = file

    def peek(self, k: int = 0) -> _Tok:
        return self.toks[min(self.i + k, len(self.toks) - 1)]

    def next(self) -> _Tok:
        tok = self.peek()
        self.i = min(self.i + 1, len(self.toks) - 1)
        return tok

    def error(self, msg: str, line: int | None = None) -> ReadError:
        return ReadError(f"{self.file}, line {self.peek().line if line is None else line}: {msg}")

    def is_kw(self, *words: str, k: int = 0) -> bool:
        tok = self.peek(k)
        return tok.kind == "name" and tok.text.upper() in words

    def expect(self, text: str, what: str = "") -> _Tok:
        tok = self.next()
        if tok.text.upper() != text.upper() or tok.kind not in ("op", "name"):
            got = tok.text or "end of file"
            raise self.error(f"expected '{text}'{what}, got '{got}'", tok.line)
        return tok

    def name(self, what: str) -> _Tok:
        tok = self.next()
        if tok.kind != "name":
            raise self.error(f"expected {what}, got '{tok.text or 'end of file'}'", tok.line)
        return tok
