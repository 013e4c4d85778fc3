"""Robot description formats: one module per format, registered by extension."""

from __future__ import annotations

from . import toml as _toml
from . import urdf as _urdf
from ._registry import read, reader, register_format, write, writer

register_format([".toml"], _toml.read, _toml.write)
register_format([".urdf"], _urdf.read, None)

__all__ = ["read", "write", "reader", "writer", "register_format"]
