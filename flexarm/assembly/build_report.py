"""What a robot build reports: the per-link table (mesher, tetrahedra, DOF, times, first
fixed-interface frequencies) and the whole build's result object."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["RobotBuild", "builds_text"]


def builds_text(builds) -> str:
    """Table of built links: mesher, tets, FE DOF, reduced DOF (``rigid`` for a rigid
    base), meshing and build time [s] (``cache`` when the superelement was read from the
    cache) and the first fixed-interface frequencies [Hz]; a ``*`` marks the fallbacks of
    ``model.mesher = "auto"`` (fTetWild on dirty CAD, Gmsh without its remesh), each
    explained below the table."""
    lines = [f"{'link':<14} {'mesher':<9} {'tets':>7} {'DOF':>7} {'reduced':>7} {'mesh_s':>7} "
             f"{'build_s':>7}  fixed-interface f [Hz]"]
    notes = []
    for lb in builds:
        f = " ".join(f"{v:.0f}" for v in lb.freq_hz[:5]) or "-"
        src = "cache" if lb.is_cached else f"{lb.seconds:7.1f}"
        kind = "rigid" if lb.superelement is None else lb.n_reduced
        mesher = (lb.mesher or "-") + ("*" if lb.mesher_note else "")
        mesh_s = f"{lb.mesh_seconds:7.1f}" if lb.mesher else "-"
        lines.append(f"{lb.name:<14} {mesher:<9} {lb.n_tets:>7} {lb.n_fe_dofs:>7} {kind:>7} "
                     f"{mesh_s:>7} {src:>7}  {f}")
        if lb.mesher_note and lb.mesher == "tetwild":
            notes.append(f"* {lb.name}: fTetWild, as {lb.mesher_note}")
        elif lb.mesher_note:  # Gmsh without its remesh of the surface
            notes.append(f"* {lb.name}: {lb.mesher}, {lb.mesher_note}")
    if any(lb.mesher == "tetwild" for lb in builds):
        notes.append("fTetWild never meshes twice alike, so a build in a fresh cache differs: "
                     "`flexarm build --pin OUT.toml` keeps these elements")
    return "\n".join(lines + notes)


@dataclass(frozen=True, eq=False)
class RobotBuild:
    """Every link of a robot built (:func:`~flexarm.assembly.build.robot_build`).

    Attributes
    ----------
    links : tuple of :class:`~flexarm.assembly.build.LinkBuild`
        Base first.
    seconds : float
        Wall time of the whole build [s].
    jobs : int
        Worker processes the links that had to be meshed were spread over (1: here).
    """

    links: tuple
    seconds: float
    jobs: int = 1

    @property
    def is_reproducible(self) -> bool:
        """True when no link's mesh came from fTetWild (which never meshes twice alike)."""
        return all(lb.mesher != "tetwild" for lb in self.links)

    def text(self) -> str:
        """The per-link table (:func:`builds_text`) and one line on the total time."""
        where = "in this process" if self.jobs == 1 else f"on {self.jobs} processes"
        return (f"{builds_text(self.links)}\n{len(self.links)} links built in "
                f"{self.seconds:.1f} s ({where})")
