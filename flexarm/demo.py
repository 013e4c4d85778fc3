"""The main job on built-in data: ``flexarm demo``.

Each step writes its tables and pictures into one output folder and returns the
lines it adds to ``index.md``; a step whose optional part (e.g. off-screen rendering)
is unavailable says so in the index instead of failing the whole demo.  Expensive
results (tetrahedra) come from the on-disk cache, so a warm run is quick.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from .fe import (
    MATERIALS,
    assemble,
    dof_split,
    mass_properties,
    modes,
    node_dofs,
    shift_invert,
)
from .fe.files import atomic_path

__all__ = ["DemoReport", "run_demo"]

log = logging.getLogger(__name__)

Progress = Callable[[str], None]


@dataclass
class DemoReport:
    """What the demo produced: output folder, index lines and headline figures."""

    folder: Path
    lines: list[str] = field(default_factory=list)
    figures: dict[str, float] = field(default_factory=dict)
    seconds: float = 0.0


def _write_csv(path: Path, header: list[str], rows) -> None:
    with atomic_path(path) as tmp:
        body = "".join(",".join(f"{v:.10g}" if isinstance(v, float) else str(v) for v in r) + "\n"
                       for r in rows)
        tmp.write_text(",".join(header) + "\n" + body)


def _part_step(out: Path, report: DemoReport, progress: Progress, size: float) -> None:
    """One built-in cast link: CAD -> Tet10 -> free and clamped modes."""
    from .meshes import hollow_link_surface, mesh_quality, tetrahedralize, write_surface, write_volume_mesh

    material = MATERIALS["cast_iron"]
    surface = hollow_link_surface()
    write_surface(out / "link.stl", surface)
    progress(f"part: tetrahedralising the built-in link (edge {size * 1e3:g} mm, cached)")
    mesh = tetrahedralize(surface, size, order=2, name="demo link")
    quality = mesh_quality(mesh, surface)
    write_volume_mesh(out / "link.vtu", mesh)
    (out / "link_quality.txt").write_text(quality.table() + "\n")

    progress(f"part: assembling K, M ({mesh.n_dofs} DOF) and solving free modes")
    t0 = time.perf_counter()
    K, M = assemble(mesh, material)
    t_asm = time.perf_counter() - t0
    free = modes(K, M, 16)
    mp = mass_properties(mesh, material.rho)

    # Clamp the bearing bore of the hub at the link origin (axis y through x = z = 0).
    r = np.hypot(mesh.points[:, 0], mesh.points[:, 2])
    bore = np.flatnonzero((r < 0.06 + 1e-3) & (np.abs(mesh.points[:, 0]) < 0.11))
    split = dof_split(mesh.n_dofs, node_dofs(bore))
    progress("part: clamped modes (hub bore at the origin fixed)")
    clamped = modes(split.condense(K), split.condense(M), 10, eigensolver=shift_invert(0.0))

    rows = [[i + 1, float(f), int(rig)] for i, (f, rig) in enumerate(zip(free.freq_hz, free.is_rigid))]
    _write_csv(out / "link_free_modes.csv", ["mode", "freq_Hz", "rigid"], rows)
    _write_csv(out / "link_clamped_modes.csv", ["mode", "freq_Hz"],
               [[i + 1, float(f)] for i, f in enumerate(clamped.freq_hz)])
    report.figures.update({
        "link_mass_kg": mp.mass,
        "link_rigid_modes": float(free.n_rigid),
        "link_first_free_Hz": float(free.freq_hz[~free.is_rigid][0]),
        "link_first_clamped_Hz": float(clamped.freq_hz[0]),
    })
    report.lines += [
        "## One cast link (part level)",
        "",
        f"Built-in hollow link, {material.name} (E {material.E / 1e9:g} GPa, ρ {material.rho:g} kg/m³): "
        f"{mesh.n_tets} Tet10, {mesh.n_dofs} DOF, mass {mp.mass:.2f} kg; assembly {t_asm:.2f} s.",
        "",
        f"- CAD: [link.stl](link.stl) · volume mesh: [link.vtu](link.vtu) · quality: [link_quality.txt](link_quality.txt)",
        f"- Free modes ([link_free_modes.csv](link_free_modes.csv)): {free.n_rigid} rigid-body modes, "
        f"first elastic {report.figures['link_first_free_Hz']:.1f} Hz",
        f"- Clamped at the origin hub ([link_clamped_modes.csv](link_clamped_modes.csv)): "
        + ", ".join(f"{f:.1f}" for f in clamped.freq_hz[:6]) + " Hz",
        "",
    ]


def run_demo(folder="flexarm-demo", progress: Progress | None = None, size: float = 0.03) -> DemoReport:
    """Run every demo step into ``folder`` and write its ``index.md``.

    Parameters
    ----------
    folder : path-like
        Output folder (created).
    progress : callable, optional
        Receives one line per step.
    size : float
        Edge length of the part-level mesh [m].
    """
    progress = progress or (lambda s: log.info(s))
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    report = DemoReport(out)
    t0 = time.perf_counter()
    _part_step(out, report, progress, size)
    report.seconds = time.perf_counter() - t0
    head = ["# flexarm demo", "", f"Run time {report.seconds:.1f} s.", ""]
    with atomic_path(out / "index.md") as tmp:
        tmp.write_text("\n".join(head + report.lines) + "\n")
    return report
