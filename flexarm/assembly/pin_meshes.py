"""A robot's tetrahedra pinned: written next to a copy of its robot file, which names them.

fTetWild (the fallback of ``model.mesher = "auto"`` for dirty CAD) never meshes twice
alike, so the same robot file built in two empty caches gives two models (the published
UR10: five of its seven links).  Pinning writes the elements a build used as volume-mesh
files (``.vtu``, readable by ParaView and meshio) and a copy of the robot file whose
links name them (``volume_meshes``, :mod:`flexarm.robot.volume_meshes`): every later
build of that file, in any cache and on any machine, uses those elements, whatever mesher
would have made them.  Pinned Tet4 files also serve ``element_order = 2`` (straight
mid-side nodes).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from ..fe.files import atomic_files
from ..fe.typing import PathType
from ..robot.description import Robot
from .link_meshes import meshed_link

__all__ = ["PinnedMeshes", "pin_meshes", "pinned_folder"]


def pinned_folder(path: PathType) -> Path:
    """The folder of the volume-mesh files pinned for the robot file ``path``.

    Examples
    --------
    >>> pinned_folder("cell/ur10_pinned.toml").as_posix()
    'cell/ur10_pinned_tets'
    """
    path = Path(path)
    return path.with_name(f"{path.stem}_tets")


@dataclass(frozen=True)
class PinnedMeshes:
    """What :func:`pin_meshes` wrote.

    Attributes
    ----------
    robot_path : Path
        The robot file naming the pinned meshes.
    mesh_size : float
        Tet edge length [m] they were made at.
    links : tuple of str
        The links pinned, base first.
    meshers : tuple of str
        What made each one's elements (``"gmsh"``, ``"tetwild"``, ``"file"``).
    n_tets : tuple of int
        Elements per link.
    files : tuple of Path
        The volume-mesh file of each link.
    """

    robot_path: Path
    mesh_size: float
    links: tuple[str, ...]
    meshers: tuple[str, ...]
    n_tets: tuple[int, ...]
    files: tuple[Path, ...]

    def text(self) -> str:
        """One row per link, then where the files went."""
        rows = [f"{'link':<16} {'made by':<9} {'tets':>7}  file"]
        rows += [f"{name:<16} {mesher:<9} {n:>7}  {Path(f).name}" for name, mesher, n, f
                 in zip(self.links, self.meshers, self.n_tets, self.files, strict=True)]
        return "\n".join(rows + [
            f"pinned {len(self.links)} links at a {self.mesh_size * 1e3:g} mm edge: "
            f"{self.robot_path} names them (in {pinned_folder(self.robot_path).name}/); a "
            f"build of it in any cache uses these elements"])


def _file_name(link: str, mesh_size: float) -> str:
    return f"{link}_{mesh_size * 1e3:g}mm.vtu"


def pin_meshes(robot: Robot, path: PathType, mesh_size: float | None = None,
               progress: Callable[[str], None] | None = None) -> PinnedMeshes:
    """Write the Tet4 elements of every link with CAD at ``mesh_size`` into
    :func:`pinned_folder` of ``path``, and at ``path`` the robot file that names them.

    The elements are those a build of ``robot`` at that size uses (read from the package
    cache after ``flexarm build``, meshed otherwise; a link that already names a file
    for that size keeps its elements); of a Tet10 robot, their corners.  All files appear
    together, the robot file last, or none of them.

    Parameters
    ----------
    robot : Robot
    path : path-like
        The robot file (TOML) to write; mesh paths in it are relative to its folder.
    mesh_size : float, optional
        Tet edge length [m] (default: the robot's ``mesh_size``).
    progress : callable (str) -> None, optional

    Returns
    -------
    PinnedMeshes

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from flexarm.robot import load_robot
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "arm.toml"
    >>> pinned = pin_meshes(load_robot(), out)  # the demo arm's own pinned elements
    >>> pinned.links[:2], pinned.meshers[:2]
    (('base', 'frame'), ('file', 'file'))
    >>> load_robot(out).links[1].volume_meshes[0.03].name
    'frame_30mm.vtu'
    """
    from ..meshes.volume_io import write_volume_mesh
    from ..robot.formats.toml import dumps, to_dict

    path = Path(path)
    h = float(robot.options.mesh_size if mesh_size is None else mesh_size)
    if not h > 0:
        raise ValueError(f"mesh_size must be > 0 m, got {h:g}")
    folder = pinned_folder(path)
    # at the robot's element order: a Tet10 build's corners are the Tet4 file (a pinned
    # Tet4 file serves both orders), where meshing Tet4 apart would give other elements
    order = robot.options.element_order
    meshed = [(i, meshed_link(lk, h, order, progress, robot.options.mesher))
              for i, lk in enumerate(robot.links) if lk.mesh is not None]
    files = tuple(folder / _file_name(robot.links[i].name, h) for i, _ in meshed)
    links = list(robot.links)
    for (i, _), file in zip(meshed, files, strict=True):
        pins = {k: v for k, v in links[i].volume_meshes.items() if abs(k / h - 1.0) > 1e-9}
        links[i] = dataclasses.replace(links[i], volume_meshes={**pins, h: file.resolve()})
    pinned = dataclasses.replace(robot, links=tuple(links))
    # paths relative to the file's final folder, not to the temporary one it is written in
    text = dumps(to_dict(pinned, path.resolve().parent))
    with atomic_files(path, *files) as (toml_tmp, *mesh_tmps):
        for (_, made), tmp in zip(meshed, mesh_tmps, strict=True):
            write_volume_mesh(tmp, made.mesh.to_tet4())
        toml_tmp.write_text(text)
    return PinnedMeshes(path, h, tuple(robot.links[i].name for i, _ in meshed),
                        tuple(made.mesher for _, made in meshed),
                        tuple(made.mesh.n_tets for _, made in meshed), files)
