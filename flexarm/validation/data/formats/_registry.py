"""Kinds of measurement file, recognised from their columns (like meshio's registry).

Each kind module exposes ``SCHEMA``, ``DATA`` (its dataclass), ``from_table``,
``read(path, limits=None)``, ``write(path, data, comments=())`` and
``to_dataframe(data)`` (the table of what ``write`` writes).
"""

from __future__ import annotations

from types import ModuleType

from ..measurements import TABLES
from ._table import Field, MeasurementFileError, Table

__all__ = ["KINDS", "register_kind", "vocabulary", "detect_kind"]

#: kind name -> module, in registration order
KINDS: dict[str, ModuleType] = {}


def register_kind(module: ModuleType) -> None:
    """Register a kind module (its ``SCHEMA.kind`` is the name); its ``to_dataframe``
    becomes the ``to_dataframe()`` method of its data class."""
    KINDS[module.SCHEMA.kind] = module
    TABLES[module.DATA] = module.to_dataframe


def vocabulary() -> dict[str, Field]:
    """Base name -> field, over every registered kind (a base means one thing)."""
    merged: dict[str, Field] = {}
    for module in KINDS.values():
        for f in module.SCHEMA.fields:
            other = merged.setdefault(f.base, f)
            assert (other.type, other.quantity) == (f.type, f.quantity), (other, f)
    return merged


def detect_kind(table: Table) -> tuple[str, bool]:
    """Kind of file from the header of ``table``, and whether it was only a guess.

    A kind whose required columns are all present wins.  Otherwise the kind is
    guessed: first by the share of its distinctive columns present (required by no
    other kind: ``series``, forces and displacements for static, ``mode`` for modal,
    ``input``, ``output``, ``re``, ``im`` for FRF, ``x, y, z, f`` for path), then by
    required columns present minus missing.  Two complete kinds, a tie, or no
    distinctive column and more missing than present raise
    :class:`MeasurementFileError`.
    """
    present = set(table.columns)
    required = {k: set(m.SCHEMA.required) for k, m in KINDS.items()}
    complete = [k for k, req in required.items() if req <= present]
    if len(complete) == 1:
        return complete[0], False
    keys = {}
    for k, req in required.items():
        own = req - set().union(*(r for o, r in required.items() if o != k))
        share = len(own & present) / len(own) if own else 0.0
        keys[k] = (share, len(req & present) - len(req - present))
    best = max(keys.values())
    plausible = best[0] > 0 or best[1] >= 0
    candidates = complete or [k for k, key in keys.items() if key == best and plausible]
    if len(candidates) == 1:
        return candidates[0], True
    where = f"{table.source}, line {table.header_line}"
    if candidates:
        nouns = " and ".join(KINDS[k].SCHEMA.noun for k in candidates)
        how = f"both {nouns}" if complete else f"{nouns} equally well"
        message = f"{where}: the columns fit {how}; cannot tell the kind of file"
    else:
        kinds = ", ".join(KINDS)
        message = (f"{where}: cannot tell the kind of measurement file from its columns "
                   f"(expected the columns of one of: {kinds}; see flexarm.validation)")
    raise MeasurementFileError(message, table.source, table.header_line)
