"""File formats of superelements, chosen by extension (like meshio's registry).

Each format module exposes ``read(path) -> Superelement`` and ``write(path, se)``.
"""

from __future__ import annotations

from pathlib import Path

from ...fe.errors import ReadError

__all__ = ["FORMATS", "EXTENSIONS", "register_format", "format_of", "read", "write"]

#: format name -> module
FORMATS: dict = {}
#: extension (with dot) -> format name
EXTENSIONS: dict[str, str] = {}


def register_format(name: str, extensions, module) -> None:
    """Register ``module`` (with ``read``/``write``) as format ``name``."""
    FORMATS[name] = module
    for ext in extensions:
        EXTENSIONS[ext] = name


def format_of(path, file_format: str | None = None) -> str:
    """Format name given explicitly or from the extension of ``path``."""
    if file_format is not None:
        if file_format not in FORMATS:
            raise ValueError(f"format must be one of {', '.join(FORMATS)}, got '{file_format}'")
        return file_format
    suffix = Path(path).suffix.lower()
    if suffix not in EXTENSIONS:
        known = ", ".join(sorted(EXTENSIONS))
        raise ValueError(f"{path}: unknown superelement extension '{suffix}' (known: {known})")
    return EXTENSIONS[suffix]


def read(path, file_format: str | None = None):
    """Read a superelement; the format follows the extension unless given."""
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(2, "no such file", str(path))
    name = format_of(path, file_format)
    try:
        return FORMATS[name].read(path)
    except ReadError:
        raise
    except (OSError, KeyError, ValueError) as exc:
        raise ReadError(f"{path}: cannot read as {name} superelement ({exc})") from None


def write(path, se, file_format: str | None = None) -> Path:
    """Write ``se`` to ``path`` (atomically); returns the path."""
    FORMATS[format_of(path, file_format)].write(Path(path), se)
    return Path(path)
