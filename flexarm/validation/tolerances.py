"""Rules of the diagnosis: noise defaults, acceptance tests, plausibility limits
(``tol.<name>``; tests may ``dataclasses.replace`` them)."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Tolerances", "tol"]


@dataclass(frozen=True)
class Tolerances:
    #: Default standard uncertainty of a tracker reading [m] (Leica AT960 in the thesis).
    tracker_sigma: float = 15e-6
    #: Accept a candidate effect only if its BIC improves by more than this.
    delta_bic_accept: float = 10.0
    #: Two-sided coverage of the chi^2_red band and of parameter intervals.
    chi2_band_coverage: float = 0.99
    interval_z: float = 1.96
    #: A candidate whose signature (at its typical size) moves the whitened data by less
    #: than this norm [-] (in units of the noise) is untestable with the data.
    untestable_norm: float = 1.0
    #: Share of a candidate's signature the current model cannot mimic, below which it is
    #: aliased with the current model's parameters.
    alias_share: float = 0.05
    #: Norm [-] (noise units, typical size) of a candidate's unique signature below which a
    #: small unique share makes it aliased.
    alias_unique_norm: float = 5.0
    #: ``|correlation|`` of two candidates' unique signatures above which they are aliased.
    alias_correlation: float = 0.95
    #: Held-out RMS must fall below this fraction of the current model's held-out RMS.
    heldout_gain: float = 0.995
    #: Number of held-out folds.
    cv_folds: int = 3
    #: What a fold holds out: "readings" (every cv_folds-th reading of every series,
    #: stratified) or "series" (whole series).
    heldout_by: str = "readings"
    #: Prior standard deviation of the baseline compliance scale factors [-] (weak).
    baseline_prior_sd: float = 1.0
    #: Relative finite-difference step of model sensitivities.
    fd_step: float = 1e-4
    #: Largest plausible backlash / lost motion [rad].
    max_backlash: float = 5e-3
    #: Relative standard uncertainty of a measured natural frequency [-] (modal tests).
    freq_noise: float = 0.005
    #: Largest relative frequency difference of a measured mode and its model partner
    #: inside a fit [-]: a measured mode farther from every model mode stays without one
    #: (at the fixed cost of :mod:`~flexarm.validation.dynamic.pairing`).
    pair_window: float = 0.3
    #: Largest plausible link compliance factor vs the CAD flexible model [-].
    max_link_compliance: float = 5.0
    #: A winner is only a proxy of an aliased candidate that gains more on the residual
    #: when their unique signatures correlate above this [-] (then it is not accepted).
    proxy_correlation: float = 0.5
    #: A candidate with less than this share of its signature unique (its amplitude is
    #: mostly borrowed from the model's other parameters) is accepted only if its refit
    #: leaves no unexplained misfit (chi^2_red in band, no residual structure) [-].
    trusted_share: float = 0.25
    #: False-alarm rate of each residual-structure test (offsets, frame, drift,
    #: outliers, tool-frame load term, joint angle, joint law), family-wise within a test.
    structure_alpha: float = 1e-3
    #: Candidates refitted per round at most (the next is tried when the best fails only
    #: on trust).
    max_refits: int = 3
    #: Largest plausible misalignment of the measurement frame: rotation [rad], scale [-].
    max_frame_error: float = 0.1
    #: Largest plausible balancer stiffness at a measured angle, as a share of the joint's
    #: gear stiffness [-].
    max_balancer_share: float = 1.0
    #: Largest plausible relative error of a load cell [-].
    max_force_scale: float = 0.2
    #: Largest plausible distance of the measured point from the TCP [m].
    max_reflector_offset: float = 0.2
    #: Largest plausible added mass, as a share of the arm's moving mass [-].
    max_added_mass_share: float = 0.3
    #: A measured channel is reversed when turning its sign lowers the shape chi-square
    #: of the paired modes by more than this many times the chi-square per observation
    #: left after the turn (at least 1) [-]: a flip is one discrete choice among the
    #: channels, so well beyond a one-parameter 5-sigma gain.
    reversed_channel_chi2: float = 25.0
    #: Largest share of the readings the outlier test may flag, one at a time [-].
    max_outlier_share: float = 0.1
    #: Uncertainty multiplier of a discounted reading (outlier) [-].
    discount_factor: float = 1e3
    #: Measurement files: a static series whose joint angles change at more than this share
    #: of its steps is a path measured under load (the loaded circle in the static schema);
    #: one that changes at fewer was moved in the middle of a load series, and is refused.
    moving_series_share: float = 0.5
    #: Measurement files: frequency lines an FRF needs at least (a peak needs a line on
    #: each side of it).
    frf_min_lines: int = 3
    #: Measurement files: a coherence may exceed 1 by this much (single-precision
    #: round-off of the analyzer) and is then taken as 1.
    coherence_round_off: float = 1e-6
    #: Universal files: largest entry of ``R R^T - I`` of a coordinate system's axes
    #: (2420 rows written in single precision by some analyzers).
    cs_orthonormal: float = 1e-6
    #: Universal files: a direction cosine below this between a measured direction and
    #: a base axis is single-precision round-off of an axis-parallel system, taken as 0.
    cs_axis_round_off: float = 1e-6
    #: Damping check: an identified ratio's scatter grows by this times its modal overlap
    #: (two overlapping modes share their damping less clearly; zoomed, refined LSCF gets
    #: the demo wrist's overlapping pair within 6 %, separated modes within a few per cent;
    #: any factor from 0.5 to 5 names its missing damper on 20/20 seeds).
    damping_overlap_widening: float = 0.5
    #: FRF comparison: a coherence is capped at 1 minus this when it turns into the weight
    #: gamma^2 / (1 - gamma^2) of a line, so that no line takes all the weight.
    coherence_floor: float = 1e-4
    #: FRF comparison: least coherence of a line where a peak is looked for.
    peak_coherence: float = 0.5
    #: Test geometry: largest distance [m] of a node from the arm's stick figure (a sensor
    #: on a link's surface sits within a casting's radius of its axis line).
    max_point_distance: float = 0.25
    #: Test geometry: two links this close to a node [m] are a tie (a node on a joint
    #: axis), decided in chain order.
    point_tie: float = 1e-9
    #: Measured path runs: largest distance [m] of a reading from the programmed path
    #: (deflections under a bar force and the tracker's registration stay within a few mm;
    #: a 10x typo or another circle of the module lies decimetres away).
    path_max_offset: float = 0.01

    #: Comparison reports: readings a picture draws one by one; past this it bins them
    #: (deflection bands per load level, a density of residual against torque), so that a
    #: million readings draw in seconds and make a readable picture of a few hundred kB.
    plot_max_points: int = 10_000
    #: Comparison reports: panels of the deflection picture (one per series up to this,
    #: else one per pose and load direction, as many at most).
    plot_max_panels: int = 36
    #: Comparison reports: load bins of a binned deflection panel, and density bins per
    #: axis of the residual picture.
    plot_bins: int = 40
    #: Comparison text: series printed one by one up to this, else one row per pose and
    #: load direction (every series stays in ``errors.csv``).
    table_max_rows: int = 60

    #: EMA: modes one LSCF fit is given at most before a wide band is split into
    #: sub-bands (one fit at the default order finds 7-10 of 25 modes over 5-800 Hz:
    #: the receptance spans decades, and the columns of the diagram crowd).
    ema_modes_per_band: int = 4
    #: EMA: frequency lines one fit is given at most before the band is split.
    ema_lines_per_band: int = 4000
    #: EMA: a sub-band reaches this share of its own width into each neighbour [-]
    #: (its modes near the edges are then fitted with their neighbours' tails).
    ema_overlap: float = 0.3
    #: EMA: LSCF order of a sub-band per expected mode in it, plus a margin (at most
    #: ``--max-order``): enough for the modes and the tails, too few to fit the noise.
    ema_order_per_mode: int = 4
    ema_order_margin: int = 8
    #: EMA: least rise of a peak of the mode indicator over its surroundings, in decades
    #: of its magnitude, for it to count as an expected mode when bands are split [-].
    ema_peak_prominence: float = 0.1
    #: EMA: two poles of overlapping sub-bands are one mode when their frequencies differ
    #: by less than this (relative) [-], ...
    ema_merge_freq: float = 0.005
    #: ... their damping ratios by less than this (relative) [-] ...
    ema_merge_damping: float = 0.3
    #: ... and the MAC of their residues exceeds this [-].
    ema_merge_mac: float = 0.9
    #: EMA: least weight of a line, as a share of the largest (a line of zero coherence
    #: still keeps the normal equations of its FRF regular) [-].
    ema_weight_floor: float = 1e-6
    #: EMA: a band whose bottom lies below this share of its top is fitted with real
    #: coefficients from 0 Hz (a mode's mirror pole sits close to it); one higher up
    #: with complex ones on the band alone (zoomed, resolving close modes) [-].
    ema_zoom_above: float = 0.1
    #: EMA: pole refinement on the lines within this many ``zeta f`` of a pole [-] ...
    ema_refine_window: float = 5.0
    #: ... and on at least this many lines ...
    ema_refine_lines: int = 30
    #: ... and a pole moved by more than this (relative frequency) is not moved [-].
    ema_refine_step: float = 0.01


tol = Tolerances()
