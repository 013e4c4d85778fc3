"""The ``flexarm`` command: a thin layer over the Python API (like meshio's ``_cli``).

One module per command group (:mod:`.demo`, :mod:`.part`, :mod:`.arm`, :mod:`.flexible`,
:mod:`.contact`, :mod:`.validation`); each command registers an ``add_args`` and a
``run`` function in :data:`~flexarm.cli._common.COMMANDS`.

Exit codes and the error boundary of :func:`main`: 0 success; 2 a user error (bad input
or option, a domain error, any OS error such as a read-only or missing folder, out of
memory), printed as one line ``flexarm <command>: error: ...`` naming the file or option;
130 interrupted (Ctrl-C; atomic writers leave nothing half-written); 1 an unexpected
exception, which is a bug: one line saying so, and ``-v`` (or ``FLEXARM_DEBUG=1``) shows its
traceback.  ``FLEXARM_DEBUG=1`` also shows the traceback of user errors.  A usage error
prints the usage and one line (a value refused by its option's type, :mod:`._numbers`:
the line alone), and :func:`main` returns 2 (``--help`` and ``--version`` exit through
argparse).
"""

from __future__ import annotations

import argparse
import logging
import os
import sys
import warnings

from . import (  # noqa: F401
    arm,
    compensate,
    contact,
    damping,
    demo,
    export,
    flexible,
    lab_data,
    part,
    plan,
    validation,
)
from ._common import COMMANDS, set_quiet
from ._numbers import NUMBER_RULE, ArgumentParser

__all__ = ["main", "parser", "COMMANDS"]


#: Command groups in the order ``flexarm --help`` lists them (the main job first).
_GROUPS = ("demo", "part", "arm", "flexible", "contact", "compensate", "validation", "plan",
           "lab_data", "damping", "export")


def _group_rank(item) -> int:
    return _GROUPS.index(item[1][2].__module__.rsplit(".", 1)[-1])


class _HelpFormatter(argparse.ArgumentDefaultsHelpFormatter):
    """Every option's default in its help, unless the help already states it or there is
    none to state (None, a switch that is off)."""

    def _get_help_string(self, action):
        help_ = action.help or ""
        if ("default" in help_ or action.default in (None, False, argparse.SUPPRESS)
                or action.default == []):  # an empty repeatable option: nothing to state
            return help_
        return super()._get_help_string(action)


def _add_verbosity(parser: argparse.ArgumentParser, default) -> None:
    """``-v``/``-q``, before the command (``default`` False) and after it (``default``
    SUPPRESS, so that an absent flag there keeps the value given before it)."""
    g = parser.add_mutually_exclusive_group()
    g.add_argument("-v", "--verbose", action="store_true", default=default,
                   help="log progress details")
    g.add_argument("-q", "--quiet", action="store_true", default=default,
                   help="no progress lines on stderr, only warnings and errors")


def parser() -> argparse.ArgumentParser:
    """The ``flexarm`` command's parser, every command and option (the CLI reference is
    generated from it)."""
    from .. import __version__

    top = ArgumentParser(
        prog="flexarm",
        description="FE substructuring and modal reduction for industrial robot arms.",
        epilog=NUMBER_RULE,
        formatter_class=_HelpFormatter,
    )
    top.add_argument("--version", action="version", version=f"flexarm {__version__}")
    _add_verbosity(top, False)
    sub = top.add_subparsers(dest="command", metavar="COMMAND")
    for name, (help_, add_args, run) in sorted(COMMANDS.items(), key=_group_rank):
        p = sub.add_parser(name, help=help_, description=help_, formatter_class=_HelpFormatter)
        add_args(p)
        _add_verbosity(p, argparse.SUPPRESS)
        p.set_defaults(_run=run)
    return top


def _one_line_warnings(message, category, filename, lineno, file=None, line=None) -> None:
    """Warnings as one line on stderr, without the source line."""
    print(f"warning: {message}", file=sys.stderr)  # noqa: T201


def main(argv: list[str] | None = None) -> int:
    """Run the CLI; returns the process exit code.

    Examples
    --------
    >>> main(["compliance", "--pose", "P1"])  # doctest: +ELLIPSIS
    TCP compliance, translations [mm/kN] (base frame):
    ...
    least stiff direction: y
    ...
    0
    """
    from ..fe.errors import FlexarmError

    cli = parser()
    try:  # a usage error (a bad option or value) has printed its line: its exit code
        args = cli.parse_args(argv)
        if args.verbose and args.quiet:
            cli.error("-v/--verbose and -q/--quiet exclude each other")
    except SystemExit as exc:
        if not exc.code:  # --help, --version
            raise
        return int(exc.code) if isinstance(exc.code, int) else 2
    logging.basicConfig(
        level=logging.INFO if args.verbose else logging.ERROR if args.quiet else logging.WARNING,
        format="%(levelname)s %(name)s: %(message)s",
    )
    set_quiet(args.quiet)
    if not getattr(args, "_run", None):  # bare ``flexarm``: help on stdout, success (git's way)
        cli.print_help()
        return 0
    old_showwarning = warnings.showwarning
    warnings.showwarning = _one_line_warnings
    try:
        return int(args._run(args) or 0)
    except (FlexarmError, ValueError, OSError, MemoryError) as exc:
        if os.environ.get("FLEXARM_DEBUG"):
            raise
        print(f"flexarm {args.command}: error: {_user_error(exc)}", file=sys.stderr)  # noqa: T201
        return 2
    except KeyboardInterrupt:  # atomic writers have removed their temporary files by now
        print(f"flexarm {args.command}: interrupted", file=sys.stderr)  # noqa: T201
        return 130
    except Exception as exc:
        if args.verbose or os.environ.get("FLEXARM_DEBUG"):
            raise
        print(f"flexarm {args.command}: internal error: {type(exc).__name__}: "  # noqa: T201
              f"{_one_line(str(exc))} (a bug in flexarm: run with -v for the traceback "
              f"and please report it)", file=sys.stderr)
        return 1
    finally:
        warnings.showwarning = old_showwarning


def _one_line(text: str) -> str:
    return " ".join(line.strip() for line in text.strip().splitlines())


def _user_error(exc: BaseException) -> str:
    """The one line of a user error: the message, or for an OS error the path and the
    reason (``out.vtu: Is a directory``)."""
    if isinstance(exc, MemoryError):
        return ("out of memory: try a coarser mesh (larger --size or --mesh-size), fewer "
                "modes or a smaller input")
    if isinstance(exc, OSError) and exc.strerror:
        # of a failed rename (os.replace of a temporary file) the target is what the user named
        path = exc.filename2 if exc.filename2 is not None else exc.filename
        return exc.strerror if path is None else f"{path}: {exc.strerror}"
    return _one_line(str(exc))


if __name__ == "__main__":
    sys.exit(main())
