"""text_table: column widths (max of header and cells), right alignment, the dashed rule, float
formatting (numpy floats too) and str for everything else, against tables written out by hand."""

from __future__ import annotations

import numpy as np

from flexarm.fe.text import text_table


def test_layout_by_hand():
    out = text_table(["name", "f"], [["mode_one", 1.0 / 3], [2, np.float64(1234567.0)]])
    assert out.splitlines() == [
        "    name            f",
        "--------  -----------",
        "mode_one     0.333333",
        "       2  1.23457e+06",
    ]


def test_custom_float_format_and_non_floats():
    """Only floats take the format: ints, None and bools print with str."""
    out = text_table(["a", "b", "c"], [[1.23456, 7, "x"], [None, 2.0, True]], floatfmt="{:.2f}")
    assert out.splitlines() == [
        "   a     b     c",
        "----  ----  ----",
        "1.23     7     x",
        "None  2.00  True",
    ]


def test_headers_only():
    assert text_table(["x", "long"], []) == "x  long\n-  ----"
