"""Dataset 55 (mode shapes) written with seven significant digits in its 13-column fields.

The 55 layout fixes every real value to a 13-column field (``FORMAT(6E13.5)``), which
C-style ``%13.5e`` fills with six significant digits: a relative round-off of up to
5e-6.  The dataset has no double-precision variant (58 and 2414 have one; SDynPy reads
shapes from 55 only).  A Fortran ``E13.5`` input field takes its decimal point from the
text, so the same 13 columns may hold more digits; pyuff and SDynPy both cut 55 records
into 13-column fields and convert each with ``float``.  :func:`e13` fills a field with
seven digits (relative round-off 5e-7) and keeps the leading blank that readers which
split on white space (UFFFiles.jl) need: a negative value with a one-digit exponent is
written with that exponent unpadded (``-1.234567E-3``, valid input for Fortran, C, Python,
Julia); one with a two-digit exponent (below 1e-9 or above 1e10) keeps six digits.

Otherwise the records are pyuff's (``pyuff.prepare_55`` dictionaries in, the same
lines out), so the file reads as before.
"""

from __future__ import annotations

import numpy as np

__all__ = ["e13", "write_55"]


def _field(v: float) -> str:
    if not np.isfinite(v):
        return f"{v:13.5e}"  # as pyuff writes it; the reader refuses it, naming the line
    for digits in (6, 5, 4, 3):
        text = f"{v:.{digits}E}"
        mantissa, exponent = text.split("E")
        for shown in (text, f"{mantissa}E{int(exponent):+d}"):
            if len(shown) <= 12:  # one blank before it, 13 columns in all
                return shown.rjust(13)
    raise ValueError(f"{v!r} does not fit a 13-column field")


def e13(values) -> str:
    """The values as consecutive 13-column fields, each with a blank before its number
    and up to seven significant digits.

    Examples
    --------
    >>> e13([1.0 / 3.0, -2.0 / 3.0, -2.5e-12, 0.0])
    ' 3.333333E-01 -6.666667E-1 -2.50000E-12 0.000000E+00'
    >>> [float(t) for t in e13([-1 / 7, 123456.789]).split()]
    [-0.1428571, 123456.8]
    """
    return "".join(_field(float(v)) for v in np.ravel(values))


def write_55(fh, dset: dict) -> None:
    """Write one 55 set (a ``pyuff.prepare_55`` dictionary of a normal (2) or complex
    (3, 7) mode, 3 values per node) to the text file ``fh``."""
    kind = int(dset["analysis_type"])
    r = [np.asarray(dset[k]) for k in ("r1", "r2", "r3")]
    is_complex = any(np.iscomplexobj(v) for v in r)
    fh.write(f"{-1:6d}\n{55:6d}{'':74s}\n")
    for k in range(1, 6):
        fh.write(f"{str(dset.get(f'id{k}', 'NONE')):<80s}\n")
    fh.write("".join(f"{v:10d}" for v in (
        int(dset.get("model_type", 1)), kind, int(dset["data_ch"]),
        int(dset["spec_data_type"]), 5 if is_complex else 2, 3)) + "\n")
    if kind == 2:
        fh.write("".join(f"{v:10d}" for v in (2, 4, int(dset["load_case"]),
                                               int(dset["mode_n"]))) + "\n")
        fh.write(e13([dset["freq"], dset.get("modal_m", 0.0), dset.get("modal_damp_vis", 0.0),
                      dset.get("modal_damp_his", 0.0)]) + "\n")
    elif kind in (3, 7):
        eig, a, b = (complex(dset.get(k, 0j)) for k in ("eig", "modal_a", "modal_b"))
        fh.write("".join(f"{v:10d}" for v in (2, 6, int(dset["load_case"]),
                                               int(dset["mode_n"]))) + "\n")
        fh.write(e13([eig.real, eig.imag, a.real, a.imag, b.real, b.imag]) + "\n")
    else:
        raise ValueError(f"55 analysis type {kind}: flexarm writes normal (2) or complex "
                         "(3, 7) modes")
    values = np.column_stack(r)
    if is_complex:
        values = np.column_stack([values.real, values.imag]).reshape(len(values), 2, 3)
        values = values.transpose(0, 2, 1).reshape(len(values), 6)
    for node, row in zip(np.asarray(dset["node_nums"], np.int64), values, strict=True):
        fh.write(f"{int(node):10d}\n{e13(row)}\n")
    fh.write(f"{-1:6d}\n")
