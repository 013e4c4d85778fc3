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

import numpy as np

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


class _Progress:
    """Start/finish lines with elapsed time on stderr; a ticking timer on a terminal."""

    def __init__(self, what: str):
        self.what = what

    def __enter__(self):
        import threading
        import time

        self.t0 = time.perf_counter()
        self._stop = threading.Event()
        sys.stderr.write(f"{self.what} ...")
        sys.stderr.flush()
        if sys.stderr.isatty():

            def tick():
                while not self._stop.wait(1.0):
                    dt = time.perf_counter() - self.t0
                    sys.stderr.write(f"\r{self.what} ... {dt:5.0f} s")
                    sys.stderr.flush()

            self._thread = threading.Thread(target=tick, daemon=True)
            self._thread.start()
        return self

    def note(self, text: str) -> None:
        sys.stderr.write(f"\n  {text}")
        sys.stderr.flush()

    def __exit__(self, exc_type, exc, tb):
        import time

        self._stop.set()
        dt = time.perf_counter() - self.t0
        status = "done" if exc_type is None else "failed"
        sys.stderr.write(f"\r{self.what} ... {status} in {dt:.1f} s\n")
        sys.stderr.flush()
        return False


def _table(headers: list[str], rows: list[list], floatfmt: str = "{:.6g}") -> str:
    """A plain fixed-width text table."""
    cells = [[floatfmt.format(c) if isinstance(c, float) else str(c) for c in r] for r in rows]
    widths = [max(len(h), *(len(r[i]) for r in cells)) if cells else len(h)
              for i, h in enumerate(headers)]
    line = "  ".join(h.rjust(w) for h, w in zip(headers, widths))
    out = [line, "  ".join("-" * w for w in widths)]
    out += ["  ".join(c.rjust(w) for c, w in zip(r, widths)) for r in cells]
    return "\n".join(out)


# --- mesh ------------------------------------------------------------------------------
def _add_mesh(p: argparse.ArgumentParser) -> None:
    p.add_argument("surface", help="CAD surface: STL, OBJ or PLY")
    p.add_argument("--units", default="m", help="length unit of the CAD file: m, mm, cm, in")
    p.add_argument("--size", type=float, required=True, help="target edge length [m]")
    p.add_argument("--order", type=int, choices=(1, 2), default=1, help="1 = Tet4, 2 = Tet10")
    p.add_argument("--no-optimize", action="store_true", help="skip fTetWild optimisation")
    p.add_argument("--no-cache", action="store_true", help="ignore the tetrahedralisation cache")
    p.add_argument("-o", "--output", required=True, help="volume mesh: .vtu, .msh, .npz")


@command("mesh", "tetrahedralise a CAD surface (pytetwild) and report mesh quality", _add_mesh)
def _run_mesh(args) -> int:
    from .meshes import mesh_part, write_volume_mesh

    if args.size <= 0:
        raise ValueError(f"--size must be a positive edge length in metres, got {args.size}")
    with _Progress(f"meshing {args.surface} (edge {args.size * 1e3:g} mm, Tet{4 if args.order == 1 else 10})") as pr:
        mesh, quality = mesh_part(
            args.surface, units=args.units, size=args.size, order=args.order,
            optimize=not args.no_optimize, cache=not args.no_cache, progress=pr.note,
        )
    write_volume_mesh(args.output, mesh)
    _print(quality.table())
    _print(f"wrote {args.output}")
    return 0


# --- modal -----------------------------------------------------------------------------
def _add_modal(p: argparse.ArgumentParser) -> None:
    p.add_argument("mesh", help="volume mesh: .vtu, .msh, .npz")
    p.add_argument("--material", default="steel",
                   help="steel | cast_iron | aluminium | nafems | 'E,nu,rho' in SI units")
    p.add_argument("--fix", default=None,
                   help="clamped nodes, e.g. 'x=min', 'z<0.01', a node-set name; "
                        "omit for a free part")
    p.add_argument("-n", "--modes", type=int, default=10, help="number of modes (elastic)")
    p.add_argument("--backend", default=None, help="sparse solver: pardiso | cholmod | splu")
    p.add_argument("--csv", default=None, help="also write the table to this CSV file")


@command("modal", "natural frequencies of one part (free or clamped)", _add_modal)
def _run_modal(args) -> int:
    from .fe import (assemble, dof_split, material_from_string, modes, node_dofs,
                     select_nodes, shift_invert)
    from .fe.files import atomic_path
    from .meshes import read_volume_mesh

    material = material_from_string(args.material)
    if args.modes < 1:
        raise ValueError(f"-n must be >= 1, got {args.modes}")
    mesh = read_volume_mesh(args.mesh).check(args.mesh)
    with _Progress(f"assembling {mesh.n_tets} Tet{4 if mesh.order == 1 else 10} ({mesh.n_dofs} DOF)"):
        K, M = assemble(mesh, material)
    if args.fix:
        try:
            nodes = select_nodes(mesh, args.fix)
        except ValueError as exc:
            raise ValueError(f"{args.mesh}: --fix {exc}") from None
        split = dof_split(mesh.n_dofs, node_dofs(nodes))
        K, M = split.condense(K), split.condense(M)
        n, solver = args.modes, shift_invert(0.0, backend=args.backend)
    else:
        nodes = np.zeros(0)
        n, solver = args.modes + 6, shift_invert(None, backend=args.backend)
    with _Progress(f"eigen-solve: {n} modes of {K.shape[0]} DOF"):
        result = modes(K, M, n, eigensolver=solver)
    rows = [[i + 1, float(f), "rigid" if r else ""] for i, (f, r) in
            enumerate(zip(result.freq_hz, result.is_rigid))]
    mass = float(M.sum()) / 3 if not args.fix else None
    _print(f"{args.mesh}: {mesh.n_tets} tets, {mesh.n_dofs} DOF, material {material.name} "
           f"(E {material.E:.4g} Pa, nu {material.nu:g}, rho {material.rho:g} kg/m^3)")
    _print(f"support: {'clamped ' + str(len(nodes)) + ' nodes (' + args.fix + ')' if args.fix else 'free'}"
           + (f"; mass {mass:.6g} kg" if mass else ""))
    if not args.fix:
        _print(f"rigid-body modes: {result.n_rigid} (a free part has 6)")
    _print(_table(["mode", "freq [Hz]", ""], rows))
    if args.csv:
        with atomic_path(args.csv) as tmp:
            tmp.write_text("mode,freq_Hz,rigid\n" + "".join(
                f"{r[0]},{r[1]:.10g},{int(bool(r[2]))}\n" for r in rows))
    return 0



# --- demo ------------------------------------------------------------------------------
def _add_demo(p: argparse.ArgumentParser) -> None:
    p.add_argument("-o", "--output", default="flexarm-demo", help="output folder")


@command("demo", "the main job on the built-in robot: tables and pictures in flexarm-demo/",
         _add_demo)
def _run_demo(args) -> int:
    from .demo import run_demo

    report = run_demo(args.output, progress=lambda s: print(s, file=sys.stderr))  # noqa: T201
    for key, value in report.figures.items():
        _print(f"{key:>28s}  {value:.6g}")
    _print(f"demo finished in {report.seconds:.1f} s: open {report.folder / 'index.md'}")
    return 0


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
