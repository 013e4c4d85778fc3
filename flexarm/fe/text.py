"""Plain fixed-width text tables, for the results that print themselves."""

from __future__ import annotations

__all__ = ["text_table", "eta_text"]


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


def eta_text(elapsed: float, done: int, total: int) -> str:
    """``", ETA 1 min 20 s"``: the rest of ``total`` items at the mean rate of the ``done``
    ones so far (``elapsed`` [s]); empty when all are done.

    Examples
    --------
    >>> eta_text(30.0, 3, 11), eta_text(5.0, 2, 3), eta_text(9.0, 3, 3)
    (', ETA 1 min 20 s', ', ETA 2 s', '')
    """
    if done >= total or done <= 0:
        return ""
    left = round(elapsed / done * (total - done))
    return f", ETA {left // 60} min {left % 60} s" if left >= 60 else f", ETA {left} s"
