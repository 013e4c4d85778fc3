"""Command line: a thin layer over the Python API (modelled on meshio's ``_cli``).

Each subcommand is a pair ``_add_<name>(parser)`` / ``_run_<name>(args) -> int``
registered in ``COMMANDS``.  Domain errors become one clear line on stderr and
exit code 2; no traceback (``FLEXARM_DEBUG=1`` shows it).
"""

from __future__ import annotations

import argparse
import logging
import os
import sys
from typing import Callable

__all__ = ["main"]

log = logging.getLogger("flexarm")


def _print(*args) -> None:
    print(*args)  # noqa: T201 - the CLI is where printing belongs


# ----------------------------------------------------------------------------- registry
# name -> (help, add_args, run)
COMMANDS: dict[str, tuple[str, Callable, Callable]] = {}


def command(name: str, help: str, add_args: Callable):
    """Decorator registering a run function with its argument builder.

    Usage::

        def _add_mesh(p): p.add_argument(...)

        @command("mesh", "tetrahedralise a CAD surface", _add_mesh)
        def _run_mesh(args) -> int: ...
    """

    def register(run):
        COMMANDS[name] = (help, add_args, run)
        return run

    return register


# ----------------------------------------------------------------------------- commands
# (subcommands are appended below this line, one block each)


# ----------------------------------------------------------------------------- main
def _parser() -> argparse.ArgumentParser:
    from . import __version__

    parser = argparse.ArgumentParser(
        prog="flexarm",
        description="FE substructuring and modal reduction for industrial robot arms.",
    )
    parser.add_argument("--version", action="version", version=f"flexarm {__version__}")
    parser.add_argument("-v", "--verbose", action="store_true", help="log progress details")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name, (help_, add_args, run) in COMMANDS.items():
        p = sub.add_parser(name, help=help_, description=help_)
        add_args(p)
        p.set_defaults(_run=run)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the CLI; returns the process exit code."""
    from .fe.errors import FlexarmError

    parser = _parser()
    args = parser.parse_args(argv)
    logging.basicConfig(
        level=logging.INFO if args.verbose else logging.WARNING,
        format="%(levelname)s %(name)s: %(message)s",
    )
    if not getattr(args, "_run", None):
        parser.print_help()
        return 1
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


if __name__ == "__main__":
    sys.exit(main())
