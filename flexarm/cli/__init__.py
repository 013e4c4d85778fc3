"""The ``flexarm`` command: a thin layer over the Python API (like meshio's ``_cli``).

One module per command group (:mod:`.demo`, :mod:`.part`, :mod:`.arm`, :mod:`.flexible`,
:mod:`.contact`, :mod:`.validation`); each command registers an ``add_args`` and a
``run`` function in :data:`~flexarm.cli._common.COMMANDS`.  Domain errors become one
line on stderr and exit code 2, never a traceback (``FLEXARM_DEBUG=1`` shows it).
"""

from __future__ import annotations

import argparse
import logging
import os
import sys
import warnings

from . import arm, contact, demo, flexible, part, validation  # noqa: F401 - they register
from ._common import COMMANDS

__all__ = ["main", "COMMANDS"]


#: Command groups in the order ``flexarm --help`` lists them (the main job first).
_GROUPS = ("demo", "part", "arm", "flexible", "contact", "validation")


def _group_rank(item) -> int:
    return _GROUPS.index(item[1][2].__module__.rsplit(".", 1)[-1])


def _parser() -> argparse.ArgumentParser:
    from .. import __version__

    parser = argparse.ArgumentParser(
        prog="flexarm",
        description="FE substructuring and modal reduction for industrial robot arms.",
    )
    parser.add_argument("--version", action="version", version=f"flexarm {__version__}")
    parser.add_argument("-v", "--verbose", action="store_true", help="log progress details")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name, (help_, add_args, run) in sorted(COMMANDS.items(), key=_group_rank):
        p = sub.add_parser(name, help=help_, description=help_)
        add_args(p)
        p.set_defaults(_run=run)
    return parser


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

    parser = _parser()
    args = parser.parse_args(argv)
    logging.basicConfig(
        level=logging.INFO if args.verbose else logging.WARNING,
        format="%(levelname)s %(name)s: %(message)s",
    )
    if not getattr(args, "_run", None):
        parser.print_help()
        return 1
    old_showwarning = warnings.showwarning
    warnings.showwarning = _one_line_warnings
    try:
        return int(args._run(args) or 0)
    except (FlexarmError, ValueError, FileNotFoundError, PermissionError) as exc:
        if os.environ.get("FLEXARM_DEBUG"):
            raise
        msg = str(exc)
        if isinstance(exc, FileNotFoundError) and exc.filename and str(exc.filename) not in msg:
            msg = f"{exc.filename}: {msg}"
        print(f"flexarm {args.command}: error: {msg}", file=sys.stderr)  # noqa: T201
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)  # noqa: T201
        return 130
    finally:
        warnings.showwarning = old_showwarning


if __name__ == "__main__":
    sys.exit(main())
