"""Robot description formats, one module each, found by extension through ``registry``:
TOML (read and write, :mod:`~flexarm.robot.formats.toml`) and URDF (read,
:mod:`~flexarm.robot.formats.urdf`).  RAPID programs (:mod:`~flexarm.robot.formats.rapid`)
describe paths, not robots; :mod:`~flexarm.robot.formats.krl` (KUKA KRL) and
:mod:`~flexarm.robot.formats.poses_csv` (a CSV of poses) write them for other controllers."""

from ...fe.errors import ReadError
from ...fe.formats import FormatRegistry
from . import toml
from .link_units import check_link_units

#: The robot description formats (:class:`~flexarm.fe.formats.FormatRegistry`).
registry = FormatRegistry("robot description")
registry.register("toml", (".toml",), toml.read, toml.write)
registry.register("urdf", (".urdf",), lambda path, **options: _urdf().read(path, **options))


def _urdf():
    """The URDF reader's module, imported when a URDF is read: it loads the CAD-surface
    tools (trimesh), which a command on a TOML robot never needs."""
    from . import urdf

    return urdf


def read(path, **options):
    """Read a robot description; the format follows the extension (``.toml``, ``.urdf``).

    ``options`` go to the format's reader (URDF: ``meshes="collision"|"visual"``).  Each
    link's CAD units are checked against the joints it carries
    (:func:`~flexarm.robot.formats.link_units.check_link_units`).

    Examples
    --------
    >>> from flexarm.robot.demo_arm import demo_robot_path
    >>> read(demo_robot_path()).name
    'flexarm demo arm (IRB 4600-60/2.05 class)'
    """
    robot = registry.read(path, **options)
    try:
        check_link_units(robot)
    except ValueError as exc:
        raise ReadError(f"{path}: {exc}") from None
    return robot


def write(path, robot, **options):
    """Write ``robot`` atomically in the format of the extension (``.toml``); returns the
    path."""
    return registry.write(path, robot, **options)


__all__ = ["registry", "read", "write"]
