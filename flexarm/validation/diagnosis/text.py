"""The diagnosis as text: identifiability, one block per model version (its fit, the
candidate table, what was accepted or dropped) and the notes, wrapped to :data:`WIDTH`.

The records (:class:`~.results.Diagnosis`, :class:`~.results.Step`,
:class:`~.results.Identifiability`) are passed in; this module does not import them, so
that ``Diagnosis.text()`` can call it."""

from __future__ import annotations

from ...fe.text import text_table

__all__ = ["WIDTH", "COLUMNS", "diagnosis_text", "identifiability_lines", "step_lines"]


#: Width of the diagnosis text [characters].
WIDTH = 120

#: What the candidate table's columns mean (printed under the first table).
COLUMNS = ("dBIC: Delta-BIC of adding the candidate (> 0 favours it); unique: share of its "
           "signature the current model cannot mimic (0-1, below 0.05 it is aliased); norm: "
           "size of its signature at a typical amplitude [noise sigma]; [n]: detail below")


def identifiability_lines(ident) -> list[str]:
    """Condition and singular values of the baseline fit with the unidentifiable
    directions named, the series in which each joint's torque changes sign, and the
    leave-one-pose-out chi2_red."""
    lines = [f"identifiability: condition {ident.condition:.3g}, singular "
             f"values {', '.join(f'{v:.3g}' for v in ident.singular_values)}"]
    lines += [_wrap(w, "  ") for w in ident.weak]
    lines += [_wrap(f"{j.replace('_', ' ')} torque changes sign in: "
                    f"{', '.join(s) if s else 'no series'}", "  ", "    ")
              for j, s in ident.sign_changes.items()]
    lines += [f"  leave-one-pose-out chi2_red on {k}: {v:.3f}"
              for k, v in ident.leave_one_pose_out.items()]
    return lines


def step_lines(i: int, step) -> list[str]:
    """Model version ``i``: its fit (chi2_red, band, RMS [µm]), a blank line before it,
    the candidate table and the verdict on the refitted best candidate."""
    lines = [f"\nv{i} {step.label}: chi2_red {step.chi2_red:.3f} (band {step.band[0]:.3f}-"
             f"{step.band[1]:.3f}), RMS fitted {step.rms_fit * 1e6:.1f} µm, held-out "
             f"{step.rms_heldout * 1e6:.1f} µm"]
    lines += [_wrap("DROPPED: " + why, "", "  ") for _, why in step.dropped]
    if step.candidates:
        details = list(dict.fromkeys(c.detail for c in step.candidates if c.detail))
        lines.append(text_table(
            ["candidate", "status", "dBIC", "unique", "norm", "see"],
            [[c.label, c.status, f"{c.dbic:.1f}", f"{c.unique:.2f}", f"{c.norm:.1f}",
              f"[{details.index(c.detail) + 1}]" if c.detail else ""]
             for c in step.candidates]))
        lines += [_wrap(f"[{k}] {d}", "  ", "      ") for k, d in enumerate(details, start=1)]
    if step.winner is not None:
        lines.append(_wrap(("ACCEPTED: " if step.accepted else "best, not accepted: ")
                           + step.explanation, "", "  "))
    return lines


def _wrap(text: str, first: str = "", rest: str | None = None) -> str:
    """``text`` wrapped to :data:`WIDTH` columns, indented by ``first`` then ``rest``."""
    import textwrap

    return textwrap.fill(text, WIDTH, initial_indent=first,
                         subsequent_indent=first if rest is None else rest,
                         break_on_hyphens=False)


def diagnosis_text(dg) -> str:
    """The whole diagnosis as the ``diagnose`` command prints it.

    Examples
    --------
    >>> from flexarm.validation.diagnosis.results import Diagnosis, Identifiability, Step
    >>> ident = Identifiability((2.0, 1.0), 2.0, ((1.0, 0.0), (0.0, 1.0)), (0.1, 0.1),
    ...                         {"joint_1": ("P1_+x",), "joint_2": ()})
    >>> step = Step("baseline", (), 1.02, (0.8, 1.2), 100.0, 15e-6, 16e-6)
    >>> print(diagnosis_text(Diagnosis((step,), ident, (), (), ("payload: untestable",))))
    identifiability: condition 2, singular values 2, 1
      joint 1 torque changes sign in: P1_+x
      joint 2 torque changes sign in: no series
    <BLANKLINE>
    v0 baseline: chi2_red 1.020 (band 0.800-1.200), RMS fitted 15.0 µm, held-out 16.0 µm
    note: payload: untestable
    """
    lines = [dg.misfit.headline()] if dg.unexplained else []
    lines += identifiability_lines(dg.identifiability)
    for i, step in enumerate(dg.steps):
        lines += step_lines(i, step)
        if i == 0 and step.candidates:
            lines.append(_wrap("columns: " + COLUMNS))
    lines += [] if dg.misfit is None else dg.misfit.lines()
    lines += [_wrap(f"note: {n}", "", "  ") for n in dg.notes]
    return "\n".join(lines)
