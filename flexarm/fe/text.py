"""Plain fixed-width text tables, for the results that print themselves."""

from __future__ import annotations

__all__ = ["text_table"]


def text_table(headers: list[str], rows: list[list], floatfmt: str = "{:.6g}") -> str:
    """A right-aligned table with a dashed rule under the headers.

    Floats are formatted with ``floatfmt``; everything else with ``str``.

    Examples
    --------
    >>> print(text_table(["mode", "freq [Hz]"], [[1, 7.5812], [2, 16.0]]))
    mode  freq [Hz]
    ----  ---------
       1     7.5812
       2         16
    """
    cells = [[floatfmt.format(c) if isinstance(c, float) else str(c) for c in r] for r in rows]
    widths = [max(len(h), *(len(r[i]) for r in cells)) if cells else len(h)
              for i, h in enumerate(headers)]
    line = "  ".join(h.rjust(w) for h, w in zip(headers, widths, strict=True))
    out = [line, "  ".join("-" * w for w in widths)]
    out += ["  ".join(c.rjust(w) for c, w in zip(r, widths, strict=False)) for r in cells]
    return "\n".join(out)
