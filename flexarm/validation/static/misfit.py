"""The verdict on the final model of a diagnosis: does it explain the data, and if not,
what shape has the misfit that is left ("unexplained misfit")?

The final model leaves an *unexplained misfit* when its chi^2_red is above its band, when
its residual keeps structure (:mod:`~flexarm.validation.static.residual_structure`), or when
readings had to be discounted as outliers.  Then none of the candidate effects explains
the data, and ``diagnose --apply`` refuses to write a robot file unless forced.  A
chi^2_red below its band is not a misfit (the stated noise is too large).
"""

from __future__ import annotations

from dataclasses import dataclass

from ..tolerances import tol
from .residual_structure import ResidualStructure

__all__ = ["Misfit", "misfit_verdict"]


@dataclass(frozen=True)
class Misfit:
    """Whether the final model explains the data, and the residual's structure.

    Attributes
    ----------
    unexplained : bool
        True if chi^2_red is above its band, a structure test fires or readings were
        discounted.
    model : str
        Label of the final model (``"baseline + joint 2 backlash"``).
    chi2_red : float
        Its chi^2_red with the stated noise.
    band : (float, float)
        The band it is judged against.
    structure : ResidualStructure
        The residual-structure tests of the final model.
    discounted : tuple of (str, int)
        Readings left out of every fit as outliers (series, step).
    missing_modes : tuple of str
        Measured modes the final model has no partner for, one line each ("the model
        lacks a mode near 108 Hz at P1 (shape: the whole arm rocks about base x)").
    channels : tuple of str
        Measured channels whose sign looks reversed, one line each.
    """

    unexplained: bool
    model: str
    chi2_red: float
    band: tuple
    structure: ResidualStructure
    discounted: tuple = ()
    missing_modes: tuple = ()
    channels: tuple = ()

    @property
    def structures(self) -> tuple[str, ...]:
        """Names of the structures found (``"drift"``, ``"outliers"``; ``"scale"`` when
        chi^2_red alone is out of band)."""
        names = [t.name for t in self.structure.found]
        if self.discounted and "outliers" not in names:
            names.insert(0, "outliers")
        if self.missing_modes:
            names.insert(0, "missing_mode")
        if self.channels:
            names.insert(0, "reversed_channel")
        if self.unexplained and not names:
            names.append("scale")
        return tuple(names)

    def headline(self) -> str:
        """The one line at the top of the report."""
        lo, hi = self.band
        if not self.unexplained:
            return (f"model explains the data: {self.model}: chi2_red {self.chi2_red:.3f} in "
                    f"its band {lo:.3f}-{hi:.3f}, no residual structure (each test at a "
                    f"false-alarm rate of {tol.structure_alpha:g})")
        what = []
        if self.chi2_red > hi:
            what.append(f"chi2_red {self.chi2_red:.3f} above its band {lo:.3f}-{hi:.3f}")
        what += [_short(self, n) for n in self.structures]
        return (f"UNEXPLAINED MISFIT: no candidate explains the data; {self.model} leaves "
                + "; ".join(what))

    def lines(self) -> list[str]:
        """The residual-structure section of the report."""
        s = self.structure
        out = ["", f"residual of the final model ({self.model}), each test at a false-alarm "
               f"rate of {tol.structure_alpha:g}:"]
        out += [f"  {'FOUND' if t.found else 'no'}: {t.line()}" for t in s.tests]
        out += [f"  FOUND: {line}" for line in self.channels + self.missing_modes]
        if self.discounted:
            out.append("  discounted as outliers (left out of every fit): "
                       + ", ".join(f"{a} step {k}" for a, k in self.discounted))
        out.append(f"  noise is about {s.noise_scale:.2f}x the stated sigma (outliers and "
                   f"the structures found left out)")
        return out


def _short(m: Misfit, name: str) -> str:
    if name == "scale":
        return (f"no structure, only scale: noise is about {m.structure.noise_scale:.1f}x "
                f"the stated sigma")
    if name == "reversed_channel":
        return "; ".join(m.channels)
    if name == "missing_mode":
        more = f" and {len(m.missing_modes) - 2} more" if len(m.missing_modes) > 2 else ""
        return "; ".join(m.missing_modes[:2]) + more
    if name == "outliers" and m.discounted:
        shown = ", ".join(f"{a} step {k}" for a, k in m.discounted[:4])
        more = " ..." if len(m.discounted) > 4 else ""
        return f"isolated outliers (discounted): {shown}{more}"
    t = m.structure.test(name)
    extra = ", ".join(x for x in (t.where, t.size) if x)
    return t.label + (f" ({extra})" if extra else "")


def misfit_verdict(model: str, chi2_red: float, band: tuple, structure: ResidualStructure,
                   discounted: tuple = (), missing_modes: tuple = (),
                   channels: tuple = ()) -> Misfit:
    """The verdict on a final model with ``chi2_red`` in or out of ``band``, its residual
    ``structure``, the readings ``discounted`` as outliers and the measured modes it has no
    partner for (``missing_modes``) and the channels that look reversed (``channels``), one
    line each.

    Examples
    --------
    >>> from flexarm.validation.static.residual_structure import ResidualStructure, StructureTest
    >>> rs = ResidualStructure((StructureTest("drift", 1e-9, 1e-3, "", "5.0 µm per reading"),),
    ...                        1.2)
    >>> m = misfit_verdict("baseline", 1.4, (0.83, 1.19), rs)
    >>> m.unexplained, m.structures
    (True, ('drift',))
    >>> m.headline()
    'UNEXPLAINED MISFIT: no candidate explains the data; baseline leaves chi2_red 1.400 \
above its band 0.830-1.190; drift in reading order (5.0 µm per reading)'
    """
    unexplained = bool(chi2_red > band[1] or structure.found or discounted or missing_modes
                       or channels)
    return Misfit(unexplained, model, float(chi2_red), tuple(band), structure,
                  tuple(discounted), tuple(missing_modes), tuple(channels))
