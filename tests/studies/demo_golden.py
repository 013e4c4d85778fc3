"""Fingerprints of the tables ``flexarm demo`` writes, to hold a run against the golden
run committed in ``golden/demo_tables.json``.

A table's fingerprint is its header, its row count and, per column, either six numbers
(sum, sum of magnitudes, first, last, min, max) or, for text, a SHA-256 of its cells.
Columns of wall-clock times (``*seconds*``) are left out.  Write the golden file from a
demo folder with ``python -m tests.studies.demo_golden FOLDER``.
"""

from __future__ import annotations

import csv
import hashlib
import json
import sys
from pathlib import Path

import numpy as np

GOLDEN = Path(__file__).with_name("golden") / "demo_tables.json"


def _column(values: list[str]):
    try:
        x = np.array([float(v) if v != "" else np.nan for v in values])
    except ValueError:
        return hashlib.sha256("\n".join(values).encode()).hexdigest()
    finite = x[np.isfinite(x)]
    if not finite.size:
        return [int(np.isnan(x).sum())]
    return [float(finite.sum()), float(np.abs(finite).sum()), float(x[0]), float(x[-1]),
            float(finite.min()), float(finite.max())]


def fingerprint(folder: Path) -> dict:
    """``{relative path: {"header", "rows", "columns"}}`` of every CSV under ``folder``."""
    out = {}
    for path in sorted(Path(folder).rglob("*.csv")):
        lines = [r for r in csv.reader(path.read_text().splitlines())
                 if r and not r[0].startswith("#")]
        header, rows = lines[0], lines[1:]
        columns = {name: _column([r[j] for r in rows]) for j, name in enumerate(header)
                   if "seconds" not in name}
        out[path.relative_to(folder).as_posix()] = {"header": header, "rows": len(rows),
                                                     "columns": columns}
    return out


def differences(run: dict, golden: dict, rtol: float = 1e-7) -> list[str]:
    """One line per table, column or number of ``run`` that differs from ``golden``."""
    out = [f"{t}: missing" for t in golden if t not in run]
    out += [f"{t}: not in the golden run" for t in run if t not in golden]
    for name in sorted(set(run) & set(golden)):
        a, b = run[name], golden[name]
        if a["header"] != b["header"] or a["rows"] != b["rows"]:
            out.append(f"{name}: header or row count differs")
            continue
        for col, want in b["columns"].items():
            got = a["columns"][col]
            if isinstance(want, str) or isinstance(got, str) or len(want) != len(got):
                if got != want:
                    out.append(f"{name} {col}: text differs")
                continue
            scale = max(abs(v) for v in want) or 1.0
            bad = [k for k, (g, w) in enumerate(zip(got, want, strict=True))
                   if abs(g - w) > rtol * scale]
            if bad:
                out.append(f"{name} {col}: {got} vs golden {want}")
    return out


if __name__ == "__main__":
    GOLDEN.parent.mkdir(exist_ok=True)
    GOLDEN.write_text(json.dumps(fingerprint(Path(sys.argv[1])), indent=1) + "\n")
    print(f"wrote {GOLDEN}")  # noqa: T201
