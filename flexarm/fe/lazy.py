"""Package namespaces whose names are imported on first use (PEP 562).

A package that re-exports its modules' names imports every module, and every library
they import, as soon as any one of them is asked for: ``flexarm.meshes`` would load
trimesh (0.8 s) for a process that only reads a volume mesh or runs one Gmsh try.
:func:`lazy_exports` gives the package a module ``__getattr__`` instead, which imports a
name's module when the name is first read (``from flexarm.meshes import mesh_surface``
included) and keeps it in the package's namespace.

Only for packages none of whose exported names is also one of its module names: the
import system sets a sub-module as an attribute of its package when it is imported,
which would then shadow the function of the same name.
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Mapping

__all__ = ["lazy_exports"]


def lazy_exports(package: str, exports: Mapping[str, tuple[str, ...]]
                 ) -> tuple[Callable[[str], object], Callable[[], list[str]], list[str]]:
    """``(__getattr__, __dir__, __all__)`` for ``package``, whose public names come from
    the modules of ``exports`` (relative module name -> the names it gives).

    Examples
    --------
    >>> getattr_, dir_, names = lazy_exports("flexarm.fe", {".mesh": ("TetMesh",)})
    >>> names, getattr_("TetMesh").__name__
    (['TetMesh'], 'TetMesh')
    >>> getattr_("nothing")
    Traceback (most recent call last):
    ...
    AttributeError: module 'flexarm.fe' has no attribute 'nothing'
    """
    where = {name: module for module, names in exports.items() for name in names}
    clash = sorted(n for n, m in where.items() if m.lstrip(".").split(".")[-1] == n)
    if clash:
        raise ValueError(f"{package}: {', '.join(clash)} would be shadowed by the module "
                         "of the same name")

    def __getattr__(name: str) -> object:
        module = where.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module, package), name)
        setattr(sys.modules[package], name, value)  # the next read is a plain lookup
        return value

    def __dir__() -> list[str]:
        return sorted(set(vars(sys.modules[package])) | set(where))

    return __getattr__, __dir__, list(where)
