"""RAPID tokens: the lexer and the token cursor the parser is built on.

``!`` comments, whitespace and the old ``%%% VERSION ... %%%`` header are dropped;
every token keeps its 1-based line so errors can name it.  Tokens are made as the
parser asks for them (a generator), and the cursor keeps only its look-ahead: a module
of millions of tokens is read in memory proportional to its longest statement, in time
linear in its size.
"""

from __future__ import annotations

import re
from collections import deque
from collections.abc import Iterable, Iterator
from itertools import islice
from typing import NamedTuple

from ...fe.errors import ReadError


class _Tok(NamedTuple):
    kind: str  # "name", "num", "str", "op", "eof"
    text: str
    line: int


_TOKEN_RE = re.compile(  # blanks before a token are part of its match: half the matches
    r"[ \t\r\f\v]*(?:(?P<nl>\n)|![^\n]*"
    r"|(?P<str>\"(?:[^\"\n]|\"\")*\")"
    r"|(?P<num>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)"
    r"|(?P<name>[A-Za-z_][A-Za-z0-9_]*)"
    r"|(?P<op>:=|<>|<=|>=|[\[\](){},;:\\+\-*/=<>])"
    r"|(?P<bad>.))"
)
#: Tokens made at a time for the look-ahead.
_BATCH = 256
_HEADER_RE = re.compile(r"\s*%%%.*?%%%", re.DOTALL)  # old "%%% VERSION:1 ... %%%" header


def _tokenize(text: str, file: str) -> Iterator[_Tok]:
    """The tokens of ``text``, then one ``eof`` token (on the line of the last one)."""
    line = 1
    pos = 0
    header = _HEADER_RE.match(text)
    if header:
        line += header.group(0).count("\n")
        pos = header.end()
    last = line
    names: dict[str, str] = {}  # one string per distinct name: memory
    for m in _TOKEN_RE.finditer(text, pos):
        kind = m.lastgroup
        if kind is None:  # a comment
            continue
        if kind == "nl":
            line += 1
            continue
        word = m.group(kind)
        if kind == "bad":
            raise ReadError(f"{file}, line {line}: unexpected character {word!r}")
        if kind == "name":
            word = names.setdefault(word, word)
        last = line
        yield _Tok(kind, word, line)
    yield _Tok("eof", "", last)  # errors at end of text


class _TokenStream:
    """Cursor over tokens with the look-ahead and error helpers of the parser.

    ``toks`` is any iterable of tokens ending with an ``eof`` token, which the cursor
    then returns for ever.  :meth:`record` collects the tokens taken until
    :meth:`recorded` (the text of a call's arguments)."""

    def __init__(self, toks: Iterable[_Tok], file: str):
        self._source = iter(toks)
        self._ahead: deque[_Tok] = deque()
        self._records: list[list[_Tok]] = []
        self.file = file

    def _fill(self, k: int) -> _Tok:
        ahead = self._ahead
        while len(ahead) <= k:
            if ahead and ahead[-1].kind == "eof":
                return ahead[-1]
            ahead.extend(islice(self._source, _BATCH))
        return ahead[k]

    def peek(self, k: int = 0) -> _Tok:
        ahead = self._ahead
        return ahead[k] if k < len(ahead) else self._fill(k)

    def next(self) -> _Tok:
        tok = self._ahead[0] if self._ahead else self._fill(0)
        if tok.kind != "eof":
            self._ahead.popleft()
        for taken in self._records:
            taken.append(tok)
        return tok

    def record(self) -> None:
        """Start collecting the tokens :meth:`next` takes."""
        self._records.append([])

    def recorded(self) -> list[_Tok]:
        """Stop the last :meth:`record`; the tokens taken since."""
        return self._records.pop()

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
