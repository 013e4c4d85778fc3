"""``flexarm ARGS`` run in-process as a user would type it: exit code, stdout, stderr."""

from __future__ import annotations

import contextlib
import io


def run_cli(args: list[str]) -> tuple[int, str, str]:
    """(exit code, stdout, stderr) of :func:`flexarm.cli.main` on ``args``."""
    from flexarm.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(args)
    return code, out.getvalue(), err.getvalue()
