"""One way to get a robot: a description file, or the built-in demo arm."""

from __future__ import annotations

from ..fe.typing import PathType
from .description import Robot

__all__ = ["load_robot"]


def load_robot(source: PathType | None = None) -> Robot:
    """The robot described by ``source`` (a ``.toml`` or ``.urdf`` file), or the built-in
    demo arm when ``source`` is None.

    Examples
    --------
    >>> load_robot().joint_names[-1]
    'joint_6'
    """
    if source is None:
        from .demo_arm import load_demo_robot

        return load_demo_robot()
    from .formats import read

    return read(source)
