"""What the demo produces: each step's index lines and headline figures, the whole
run's result, and the one CSV writer the demo's own tables go through.

Every result is frozen: lines are tuples and figures read-only mappings, built once
when the step (or the run) finishes.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType

from ..fe.files import atomic_path

__all__ = ["Progress", "StepResult", "DemoResult", "write_table"]

#: Receives one progress line per stage of a step.
Progress = Callable[[str], None]


def _freeze(result, lines: Iterable[str], figures: Mapping[str, float]) -> None:
    object.__setattr__(result, "lines", tuple(lines))
    object.__setattr__(result, "figures", MappingProxyType(dict(figures)))


@dataclass(frozen=True, eq=False)
class StepResult:
    """What one demo step adds to the run.

    Attributes
    ----------
    lines : tuple of str
        Markdown lines of the step's section in ``index.md``.
    figures : mapping of str to float
        Headline figures (read-only), the unit at the end of each name (``_Hz``,
        ``_mm``, ``_kg``, ``_um``; ``_share`` and ``chi2`` are dimensionless).

    Examples
    --------
    >>> import pickle
    >>> step = StepResult(["## A step"], {"f1_Hz": 7.5})
    >>> pickle.loads(pickle.dumps(step)).figures["f1_Hz"]
    7.5
    """

    lines: tuple[str, ...] = ()
    figures: Mapping[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        _freeze(self, self.lines, self.figures)

    def __reduce__(self):
        # A mappingproxy does not pickle, and the worker process returns its steps by pickle.
        return (type(self), (self.lines, dict(self.figures)))


@dataclass(frozen=True, eq=False)
class DemoResult:
    """The demo run: its folder, the lines of ``index.md`` below the title, the
    headline figures of every step, and the wall time.

    Attributes
    ----------
    folder : Path
        Output folder.
    lines : tuple of str
        Every step's index lines, in step order.
    figures : mapping of str to float
        Every step's figures, in step order (read-only).
    seconds : float
        Wall time of the run [s].
    """

    folder: Path
    lines: tuple[str, ...]
    figures: Mapping[str, float]
    seconds: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "folder", Path(self.folder))
        _freeze(self, self.lines, self.figures)

    def __reduce__(self):
        return (type(self), (self.folder, self.lines, dict(self.figures), self.seconds))

    @classmethod
    def of(cls, folder, steps: Iterable[StepResult], seconds: float) -> DemoResult:
        """The run made of ``steps`` (lines and figures joined in order).

        Examples
        --------
        >>> run = DemoResult.of("out", [StepResult(["a"], {"x_mm": 1.0}),
        ...                             StepResult(["b"], {"y_mm": 2.0})], 3.0)
        >>> run.lines, dict(run.figures)
        (('a', 'b'), {'x_mm': 1.0, 'y_mm': 2.0})
        """
        steps = tuple(steps)
        return cls(folder, (line for s in steps for line in s.lines),
                   {k: v for s in steps for k, v in s.figures.items()}, seconds)

    def index_text(self) -> str:
        """The text of ``index.md``: title, run time, then every step's section."""
        head = ("# flexarm demo", "", f"Run time {self.seconds:.1f} s.", "")
        return "\n".join(head + self.lines) + "\n"


def write_table(path, header: Sequence[str], rows: Iterable[Sequence]) -> Path:
    """Write ``rows`` under ``header`` as CSV, atomically.

    Floats are written with 10 significant digits, everything else with ``str``;
    units belong in the column names.

    Examples
    --------
    >>> import tempfile
    >>> p = write_table(Path(tempfile.mkdtemp()) / "t.csv", ["mode", "freq_Hz"], [[1, 2 / 3]])
    >>> p.read_text()
    'mode,freq_Hz\\n1,0.6666666667\\n'
    """
    body = "".join(",".join(f"{v:.10g}" if isinstance(v, float) else str(v) for v in row)
                   + "\n" for row in rows)
    with atomic_path(path) as tmp:
        tmp.write_text(",".join(header) + "\n" + body)
    return Path(path)
