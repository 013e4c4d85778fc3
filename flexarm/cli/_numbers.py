"""Option types: every number typed on the command line read by :mod:`flexarm.fe.quantities`.

A factory here returns argparse's ``type=`` for one kind of option value (a number with
its unit and range, a count, a comma list, ``start:stop:step`` levels, a ``LO:HI`` band,
an effect spec).  The rule every value follows is that module's: a bare number is in the
unit the option's help names, a unit suffix is accepted (``--force 0.8kN``), a unit is
required where a bare number would be ambiguous (``lab --noise 25um``), and a value must be
finite and in range.

:class:`ArgumentParser` gives each such type its option's name, so that a refused value is
one line naming both, ``flexarm compliance: error: --force 1e30: must be > 0 and <= 1e6 N``,
exit code 2, before any work (other usage errors keep argparse's usage line).  It also
reads ``-5e5``, ``-0.1mrad`` or ``-inf`` after an option as its value (argparse alone
knows ``-5`` and ``-.5`` only): a negative value is accepted or refused by its range,
never taken for an option.

The readers import :mod:`flexarm.fe` only when a value is read.
"""

from __future__ import annotations

import argparse
import math
import re
from collections.abc import Callable

__all__ = ["ArgumentParser", "NUMBER_RULE", "number", "numbers", "count", "counts", "levels",
           "band", "or_word", "effect", "effects"]

#: The rule, for the command's help.
NUMBER_RULE = ("Numbers: a bare number is in the unit the option's help names (--force 800 "
               "is 800 N); a unit suffix is accepted (--force 0.8kN, --step 0.5cm); lengths "
               "and angles whose unit could be mistaken need one (lab --noise 25um, --effect "
               "backlash:j2=0.1mrad). nan, inf and values outside an option's plausible "
               "range are refused.")

#: A negative number, with or without a unit or more comma-separated values: a value.
_NEGATIVE = re.compile(r"^-(?:(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?\S*"
                       r"|inf(?:inity)?|nan)$", re.I)
#: Joints an effect may name before the robot is known (its own count is checked later).
_ANY_JOINT = 99


class Reader:
    """argparse's ``type=``: ``read(text, what)`` with ``what`` the option's name (given by
    :class:`ArgumentParser`); its ValueError becomes the line argparse prints."""

    def __init__(self, read: Callable[[str, str | None], object], name: str,
                 what: str | None = None):
        self.read, self.__name__, self.what = read, name, what

    def named(self, what: str) -> Reader:
        """The same reader naming option ``what`` in its messages."""
        return Reader(self.read, self.__name__, what)

    def __call__(self, text: str):
        try:
            return self.read(text, self.what)
        except ValueError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None


class ArgumentParser(argparse.ArgumentParser):
    """argparse's parser reading negative numbers as values and refusing a bad value in
    one line (sub-commands' parsers are of the same class)."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = _NEGATIVE

    def add_argument(self, *args, **kwargs):
        reader = kwargs.get("type")
        options = [a for a in args if a.startswith("-")]
        if isinstance(reader, Reader) and options:  # named as argparse names it
            kwargs["type"] = reader.named("/".join(options))
        return super().add_argument(*args, **kwargs)

    def error(self, message: str):
        found = re.match(r"argument (\S+): (.*)", message, flags=re.S)
        if found and found.group(2).startswith(found.group(1) + " "):  # a Reader's line
            self.exit(2, f"{self.prog}: error: {found.group(2)}\n")
        super().error(message)


def _quantity(kind, unit, low, high, kw):
    from ..fe.quantities import Quantity

    return Quantity(kind, unit, low, high, **kw)


def number(kind: str, unit: str | None = None, low: float = -math.inf,
           high: float = math.inf, **kw) -> Reader:
    """A value of quantity ``kind`` in ``unit``, ``low`` to ``high`` (in ``unit``);
    ``kw``: ``open_low``, ``open_high``, ``bare``, ``result``, ``hint`` of
    :class:`~flexarm.fe.quantities.Quantity`.

    Examples
    --------
    >>> number("force", "N", 0, 1e6)("0.8kN")
    800.0
    """
    return Reader(lambda text, what: _quantity(kind, unit, low, high, kw).parse(text, what),
                  kind)


def numbers(kind: str, unit: str | None = None, low: float = -math.inf,
            high: float = math.inf, n: int | None = None, **kw) -> Reader:
    """Comma-separated values of :func:`number` (exactly ``n`` if given).

    Examples
    --------
    >>> numbers("length", "mm", -1e4, 1e4, n=3)("10,-5,0.1cm")
    [10.0, -5.0, 1.0]
    """
    def read(text, what):
        from ..fe.quantities import parse_list

        return parse_list(text, _quantity(kind, unit, low, high, kw), what, n=n)

    return Reader(read, f"{kind} list")


def levels(kind: str, unit: str | None = None, low: float = -math.inf,
           high: float = math.inf, max_count: int = 1000, **kw) -> Reader:
    """``start:stop:step`` or a comma list of :func:`number`, as a (k,) array.

    Examples
    --------
    >>> levels("force", "N", 0, 1e6)("0:400:200").tolist()
    [0.0, 200.0, 400.0]
    """
    def read(text, what):
        from ..fe.quantities import parse_levels

        return parse_levels(text, _quantity(kind, unit, low, high, kw), what, max_count)

    return Reader(read, f"{kind} levels")


def band(kind: str, unit: str | None = None, low: float = -math.inf,
         high: float = math.inf, **kw) -> Reader:
    """``LO:HI`` of :func:`number` with LO < HI.

    Examples
    --------
    >>> band("frequency", "Hz", 0, 1e5)("2:0.16kHz")
    (2.0, 160.0)
    """
    def read(text, what):
        from ..fe.quantities import parse_band

        return parse_band(text, _quantity(kind, unit, low, high, kw), what)

    return Reader(read, f"{kind} band")


def count(low: int = 0, high: int = 2**31 - 1) -> Reader:
    """A whole number ``low`` to ``high``.

    Examples
    --------
    >>> count(2, 200)("24")
    24
    """
    def read(text, what):
        from ..fe.quantities import parse_count

        return parse_count(text, what, low, high)

    return Reader(read, "count")


def counts(low: int = 0, high: int = 2**31 - 1) -> Reader:
    """Comma-separated :func:`count` values.

    Examples
    --------
    >>> counts(0, 100)("0,5,10")
    [0, 5, 10]
    """
    def read(text, what):
        from ..fe.quantities import parse_count

        fields = text.split(",")
        if not text.strip() or any(not f.strip() for f in fields):
            raise ValueError(f"{what or 'value'} {text!r}: expected comma-separated whole "
                             "numbers, none empty")
        return [parse_count(f.strip(), what, low, high) for f in fields]

    return Reader(read, "count list")


def or_word(word: str, other: Reader) -> Reader:
    """``word`` itself, or what ``other`` reads (``--wall auto`` or ``--wall 8mm``).

    Examples
    --------
    >>> wall = or_word("auto", number("length", "m", 0, 1, open_low=True))
    >>> wall("auto"), wall("8mm")
    ('auto', 0.008)
    """
    return Reader(lambda text, what: word if text.strip().lower() == word
                  else other.read(text, what), other.__name__)


def _effect(text: str, what: str | None) -> str:
    from ..robot.effects import parse_effect

    try:
        parse_effect(text, _ANY_JOINT)
    except ValueError as exc:  # "effect 'SPEC': ...": the option's name in front
        message = str(exc)
        raise ValueError(f"{what} {message.removeprefix('effect ')}" if what else message
                         ) from None
    return text


#: An ``--effect`` spec whose values are checked now (units, signs, ranges; the joint
#: number against the robot later); the text itself is the value.
effect = Reader(_effect, "effect")

#: ``;``-separated effect specs (``--hypotheses``), as a list of texts.
effects = Reader(lambda text, what: [_effect(t.strip(), what) for t in text.split(";")
                                     if t.strip()], "effects")
