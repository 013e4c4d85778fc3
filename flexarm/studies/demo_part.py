"""The demo's part-level step: one built-in cast link from CAD to Tet10, its free and
clamped modes (:func:`~flexarm.studies.part_modes.part_modes`) and its Craig-Bampton
superelement with mode pictures."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from ..fe import MATERIALS, Material, TetMesh, assemble
from ..fe.typing import IntArray
from .demo_results import Progress, StepResult, write_table
from .part_modes import part_modes

__all__ = ["part_step", "hub_bore_nodes"]

#: Hub bores of the built-in link: name and centre on the link's x axis [m].
_HUBS = (("hub_a", 0.0), ("hub_b", 0.8))


def part_step(out: Path, progress: Progress, size: float = 0.03) -> StepResult:
    """Mesh the built-in hollow link, solve its free and clamped modes and reduce it.

    Parameters
    ----------
    out : Path
        Output folder: ``link.stl``, ``link.vtu``, ``link_quality.txt``,
        ``link_free_modes.csv``, ``link_clamped_modes.csv``, ``link_cb10.h5`` and the
        superelement's mode pictures.
    progress : callable (str) -> None
        One line per stage.
    size : float
        Target tet edge length [m].
    """
    material = MATERIALS["cast_iron"]
    mesh = _link_mesh(out, size, progress)
    progress(f"part: assembling K, M ({mesh.n_dofs} DOF) and solving free modes")
    t0 = time.perf_counter()
    K, M = assemble(mesh, material)
    t_asm = time.perf_counter() - t0
    free = part_modes(mesh, material, 10, matrices=(K, M))
    free.write_csv(out / "link_free_modes.csv")
    progress("part: clamped modes (hub bore at the origin fixed)")
    clamped = part_modes(mesh, material, 10, fix=hub_bore_nodes(mesh), matrices=(K, M))
    write_table(out / "link_clamped_modes.csv", ["mode", "freq_Hz"],
                [[i + 1, float(f)] for i, f in enumerate(clamped.freq_hz)])
    se_dofs, se_lines = _superelement(out, mesh, material, progress)
    figures = {
        "link_mass_kg": free.mass,
        "link_rigid_modes": float(free.n_rigid),
        "link_first_free_Hz": free.first_elastic_hz,
        "link_first_clamped_Hz": float(clamped.freq_hz[0]),
        "link_superelement_dof": float(se_dofs),
    }
    lines = [
        "## One cast link (part level)",
        "",
        f"Built-in hollow link, {material.name} (E {material.E / 1e9:g} GPa, "
        f"ρ {material.rho:g} kg/m³): "
        f"{mesh.n_tets} Tet10, {mesh.n_dofs} DOF, mass {free.mass:.2f} kg; "
        f"assembly {t_asm:.2f} s.",
        "",
        "- CAD: [link.stl](link.stl) · volume mesh: [link.vtu](link.vtu) · "
        "quality: [link_quality.txt](link_quality.txt)",
        f"- Free modes ([link_free_modes.csv](link_free_modes.csv)): "
        f"{free.n_rigid} rigid-body modes, first elastic {free.first_elastic_hz:.1f} Hz",
        "- Clamped at the origin hub ([link_clamped_modes.csv](link_clamped_modes.csv)): "
        + ", ".join(f"{f:.1f}" for f in clamped.freq_hz[:6]) + " Hz",
        *se_lines,
        "",
    ]
    return StepResult(lines, figures)


def hub_bore_nodes(mesh: TetMesh) -> IntArray:
    """(c,) nodes of the built-in link on the bearing bore of its origin hub: within
    61 mm of the hub axis (y through x = z = 0), i.e. the 60 mm bore plus 1 mm for
    round-off of the meshed surface."""
    r = np.hypot(mesh.points[:, 0], mesh.points[:, 2])
    return np.flatnonzero(r < 0.06 + 1e-3)


def _link_mesh(out: Path, size: float, progress: Progress) -> TetMesh:
    """Tet10 mesh of the built-in link [m] (cached), with its CAD, mesh and quality files."""
    from ..meshes import (
        hollow_link_surface,
        mesh_quality,
        tetrahedralize,
        write_surface,
        write_volume_mesh,
    )

    surface = hollow_link_surface()
    write_surface(out / "link.stl", surface)
    progress(f"part: tetrahedralising the built-in link (edge {size * 1e3:g} mm, cached)")
    mesh = tetrahedralize(surface, size, order=2, name="demo link")
    write_volume_mesh(out / "link.vtu", mesh)
    (out / "link_quality.txt").write_text(mesh_quality(mesh, surface).table() + "\n")
    return mesh


def _superelement(out: Path, mesh: TetMesh, material: Material,
                  progress: Progress) -> tuple[int, list[str]]:
    """Craig-Bampton superelement of the link on its two hub bores (``link_cb10.h5``)
    and pictures of its first mode: its DOF count and index lines."""
    from ..reduction import CylinderRegion, reduce_with_stats
    from ..reduction.formats import write as write_superelement

    bores = [CylinderRegion(name, (x, 0.0, 0.0), (0.0, 1.0, 0.0), 0.0, 0.065, 0.1)
             for name, x in _HUBS]
    progress("part: Craig-Bampton superelement (RBE2 on both bores, 10 modes)")
    se, stats = reduce_with_stats(mesh, material, bores, "rbe2", "cb", 10)
    write_superelement(out / "link_cb10.h5", se)
    lines = [
        f"- Craig-Bampton superelement [link_cb10.h5](link_cb10.h5): {stats.n_full} → "
        f"{stats.n_reduced} DOF in {stats.total_seconds:.1f} s; fixed-interface modes "
        + ", ".join(f"{f:.0f}" for f in se.freq_hz[:5]) + " Hz",
    ]
    try:
        from ..reduction.render import render_mode

        render_mode(se, 1, out / "link_fixed_mode1.png", boundary="fixed")
        render_mode(se, 1, out / "link_free_mode1.gif", boundary="free")
        lines += ["", "  ![fixed-interface mode 1](link_fixed_mode1.png) "
                      "![free mode 1](link_free_mode1.gif)"]
    except Exception as exc:  # noqa: BLE001 - pictures are optional; say why they are missing
        lines += [f"- (no pictures: {exc})"]
    return se.n_dofs, lines
