"""The results of a diagnosis (:func:`~flexarm.validation.diagnosis.search.diagnose`):
identifiability, one record per model version (its fit, the candidate ranking, the
accepted or best refitted candidate) and the notes on what the data cannot test.  Their
text is :mod:`flexarm.validation.diagnosis.text`."""

from __future__ import annotations

from dataclasses import dataclass, field, fields

__all__ = ["CandidateReport", "Checks", "Winner", "Step", "Identifiability", "Diagnosis"]


@dataclass(frozen=True)
class CandidateReport:
    """Outcome for one candidate against one model version.

    Attributes
    ----------
    name, label : str
        Candidate key (``"backlash_j2"``) and its readable name (``"joint 2 backlash"``).
    status : str
        ``"accepted"``, ``"rejected"``, ``"aliased"`` or ``"untestable"``.
    dbic : float
        ΔBIC of the score test against the current model (dimensionless; > 0 favours it).
    unique : float
        Share of the candidate's whitened signature the current model cannot mimic (0-1).
    norm : float
        Whitened norm of its signature at typical size [noise sigma].
    detail : str
        Why this status (alias partner, loads that would test it, failed checks).
    """

    name: str
    label: str
    status: str
    dbic: float
    unique: float
    norm: float
    detail: str = ""


@dataclass(frozen=True)
class Checks:
    """Acceptance checks of the refitted best candidate; it is accepted if all pass.

    Attributes
    ----------
    dbic : bool
        ΔBIC of the physical refit > ``tol.delta_bic_accept``.
    heldout : bool
        Held-out RMS below ``tol.heldout_gain`` times the current model's (True when
        the diagnosis runs without held-out validation).
    plausible : bool
        Fitted amplitudes inside their physical range.
    interval : bool
        Their ``tol.interval_z`` sigma intervals exclude zero (one is enough for the
        coupled wrist).
    distinct : bool
        No aliased candidate correlated with it explains more (False: it is a proxy).
    trusted : bool
        Its unique share of the signature is at least ``tol.trusted_share``, or its refit
        leaves no load-linear structure (tool frame, joint angle, measurement frame): an
        amplitude mostly borrowed from the other parameters is trusted only if it does
        not stand in for such a structure.
    clean : bool
        Its refit leaves no measurement-side structure (offsets, drift, frame): an effect
        fitted under such a fault is a proxy of it.
    """

    dbic: bool
    heldout: bool
    plausible: bool
    interval: bool
    distinct: bool = True
    trusted: bool = True
    clean: bool = True

    @property
    def passed(self) -> bool:
        return all(getattr(self, f.name) for f in fields(self))

    @property
    def failed(self) -> tuple[str, ...]:
        """Names of the failed checks, in field order."""
        return tuple(f.name for f in fields(self) if not getattr(self, f.name))


@dataclass(frozen=True)
class Winner:
    """The best-ranked candidate of one step, refitted with the current model.

    Attributes
    ----------
    name, label : str
        Candidate key and readable name.
    dbic : float
        ΔBIC of the physical refit against the current model (dimensionless).
    params : dict of str -> (float, float)
        Fitted amplitude name -> (value, standard deviation), SI units of the effect's
        parameter (e.g. rad for a backlash width, rad/(N m) for a compliance).
    grid_name : str or None
        Shape parameter found by search (``"threshold"``, ``"radius"``), if any.
    grid_value : float or None
        Its fitted value, SI (e.g. N m).
    grid_sd : float
        Its standard deviation, SI (NaN without a shape parameter).
    checks : Checks
        The acceptance checks.
    chi2_red_after : float
        chi^2_red of the model with this candidate added.
    rms_heldout_after, rms_fit_after : float
        Held-out RMS (0 without held-out validation) and fitted RMS of that model [m].
    """

    name: str
    label: str
    dbic: float
    params: dict[str, tuple[float, float]]
    grid_name: str | None
    grid_value: float | None
    grid_sd: float
    checks: Checks
    chi2_red_after: float
    rms_heldout_after: float
    rms_fit_after: float


@dataclass(frozen=True)
class Step:
    """One model version and the candidate ranking against it.

    Attributes
    ----------
    label : str
        ``"baseline + joint 2 backlash + ..."``.
    effects : tuple of Effect
        The fitted model (SI parameters).
    chi2_red : float
        GLS chi^2 per degree of freedom with the stated noise.
    band : (float, float)
        Its acceptance band for ``dof``.
    dof : float
        Degrees of freedom (observations minus effective fitted parameters).
    rms_fit, rms_heldout : float
        RMS residual of the fitted and of the held-out series [m] (NaN: not computed).
    candidates : tuple of CandidateReport
        Ranked: accepted, rejected, aliased, untestable; by ΔBIC within each.
    winner : Winner or None
        The refitted best testable candidate (None if there was none).
    accepted : bool
        ``winner`` passed every check.
    explanation : str
        The winner explained in one sentence.
    freq_rms : float
        RMS relative error [-] of the paired measured frequencies (NaN: no modal data).
    n_unpaired : int
        Measured modes without a partner in this version.
    dropped : tuple of (str, str)
        Effects accepted earlier that this version left out again: (candidate name, why).
    """

    label: str
    effects: tuple
    chi2_red: float
    band: tuple
    dof: float
    rms_fit: float
    rms_heldout: float
    candidates: tuple = ()
    winner: Winner | None = None
    accepted: bool = False
    explanation: str = ""
    freq_rms: float = float("nan")
    n_unpaired: int = 0
    dropped: tuple = ()


@dataclass(frozen=True)
class Identifiability:
    """How well the data determine the baseline (per-joint torsion compliance scales).

    Attributes
    ----------
    singular_values : tuple of float, (n_free,)
        Singular values of the whitened sensitivity matrix (whitened residual per unit
        compliance scale, dimensionless), largest first.
    condition : float
        Largest over smallest singular value (NaN without free parameters).
    correlation : tuple of tuple of float, (n_free, n_free)
        Correlation matrix of the fitted scales.
    stderr : tuple of float, (n_free,)
        Standard deviation of each fitted scale (dimensionless; nominal scale 1).
    sign_changes : dict of str -> tuple of str
        ``"joint_1"`` ... -> the series in which that joint's torque changes sign.
    leave_one_pose_out : dict of str -> float
        Pose label -> chi^2_red on that pose with the model fitted on the other poses
        (empty with fewer than three poses).
    weak : tuple of str
        The parameter combinations the data cannot tell apart, in words
        (:func:`.identifiability.weak_directions`).
    """

    singular_values: tuple[float, ...]
    condition: float
    correlation: tuple[tuple[float, ...], ...]
    stderr: tuple[float, ...]
    sign_changes: dict[str, tuple[str, ...]]
    leave_one_pose_out: dict[str, float] = field(default_factory=dict)
    weak: tuple[str, ...] = ()


@dataclass(frozen=True)
class Diagnosis:
    """All steps, the identifiability report and the final accepted effects.

    Attributes
    ----------
    steps : tuple of Step
        One per model version, the baseline first.
    identifiability : Identifiability
        Of the baseline fit.
    accepted : tuple of Effect
        The accepted effects with their fitted parameters (SI).
    final_effects : tuple of Effect
        The full final model (baseline scales included).
    notes : tuple of str
        Effects these data cannot test, and why.
    misfit : Misfit or None
        The verdict on the final model (:mod:`~flexarm.validation.static.misfit`): does it explain
        the data, and the structure of its residual.
    """

    steps: tuple
    identifiability: Identifiability
    accepted: tuple
    final_effects: tuple
    notes: tuple = field(default_factory=tuple)
    misfit: object = None

    @property
    def unexplained(self) -> bool:
        """The final model leaves an unexplained misfit (False without a verdict)."""
        return bool(self.misfit is not None and self.misfit.unexplained)

    @property
    def final(self) -> Step:
        return self.steps[-1]

    @property
    def named(self) -> tuple[str, ...]:
        """Candidate names of the effects in the final model, in the order accepted
        (those a later version dropped again left out)."""
        gone = {name for s in self.steps for name, _ in s.dropped}
        return tuple(s.winner.name for s in self.steps
                     if s.accepted and s.winner.name not in gone)

    def text(self) -> str:
        """The diagnosis as ``diagnose`` prints it
        (:func:`~flexarm.validation.diagnosis.text.diagnosis_text`)."""
        from .text import diagnosis_text

        return diagnosis_text(self)

    def __repr__(self) -> str:
        accepted = ", ".join(e.label for e in self.accepted) or "nothing"
        return (f"Diagnosis({len(self.steps)} model versions, accepted: {accepted}; final "
                f"chi2_red {self.final.chi2_red:.3f} (band {self.final.band[0]:.3f}-"
                f"{self.final.band[1]:.3f}), RMS {self.final.rms_fit * 1e6:.1f} µm"
                f"{', unexplained misfit' if self.unexplained else ''})")

    def to_dataframe(self):
        """One row per candidate and model version: ``version``, ``model``, ``candidate``,
        ``status``, ``dBIC``, ``unique``, ``norm`` (as in the report's table) and
        ``detail`` (a ``pandas.DataFrame``; pandas is optional)."""
        from ...fe.notebook import data_frame

        rows = [(i, s.label, c) for i, s in enumerate(self.steps) for c in s.candidates]
        return data_frame({"version": [i for i, _, _ in rows],
                           "model": [m for _, m, _ in rows],
                           "candidate": [c.label for *_, c in rows],
                           "status": [c.status for *_, c in rows],
                           "dBIC": [c.dbic for *_, c in rows],
                           "unique": [c.unique for *_, c in rows],
                           "norm": [c.norm for *_, c in rows],
                           "detail": [c.detail for *_, c in rows]})
