"""All numerical tolerances in one place (like trimesh's ``constants.tol``).

Algorithms read ``tol.<name>``; tests may build their own :class:`Tolerances` with
``dataclasses.replace``.  No tolerance literal lives inside an algorithm.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Tolerances", "tol"]


@dataclass(frozen=True)
class Tolerances:
    #: Relative volume below which a tetrahedron counts as degenerate (|V| / mean |V|).
    degenerate_volume: float = 1e-12
    #: Relative asymmetry ||A - A^T||_max / ||A||_max accepted for "symmetric" matrices.
    symmetry: float = 1e-10
    #: Rigid-body modes: |omega^2| below this fraction of median(K_ii / M_ii) counts as zero.
    rigid_mode: float = 1e-12
    #: Eigenvalue shift for free parts, as a fraction of median(K_ii / M_ii): small, so that
    #: thin parts (first elastic omega^2 ~ 1e-9 of the mesh scale) still converge quickly.
    auto_shift: float = 1e-10
    #: ARPACK relative accuracy (0 = machine precision).
    arpack: float = 0.0
    #: Plausible size of one robot part [m]: outside this, the units are probably wrong.
    part_size_min: float = 1e-3
    part_size_max: float = 20.0
    #: SuperLU pivot below this fraction of the largest: the matrix counts as singular.
    singular_pivot: float = 1e-12
    #: Geometric coincidence of points [m].
    point_merge: float = 1e-9
    #: CAD surfaces: smallest / largest principal extent below this counts as flat.
    surface_flatness: float = 1e-9
    #: CAD surfaces: enclosed volume below this times (largest extent)^3 counts as zero.
    surface_min_volume: float = 1e-9
    #: Tetrahedra with a dihedral angle below this [deg] are slivers (the mesher retries).
    sliver_dihedral_deg: float = 5.0
    #: pytetwild envelope: allowed surface deviation / bounding-box diagonal.
    tet_envelope: float = 1e-3
    #: |V_tets - V_surface| / V_surface above which tetrahedralisation logs a warning.
    tet_volume_warn: float = 1e-2


    #: Unit-quaternion check of RAPID robtargets (they are printed to ~1e-4..1e-9).
    quaternion_norm: float = 1e-4
    #: Three points are collinear when the triangle area is below this times |a||b|.
    collinear: float = 1e-9
    #: Below this angle [rad] SLERP falls back to normalised linear interpolation.
    slerp_small_angle: float = 1e-9
    #: Region nodes: smallest / largest eigenvalue of the (weighted) second-moment tensor
    #: about the centroid below which they count as collinear (cannot carry a rotation).
    region_collinear: float = 1e-8
    #: Nodes needed at least in a region to carry 6 DOFs (3 non-collinear points).
    min_region_nodes: int = 3
    #: Relative asymmetry accepted when loading a superelement file.
    file_symmetry: float = 1e-10
    #: Most negative eigenvalue of a loaded K accepted, relative to its largest.
    file_psd: float = 1e-8
    #: Render-probe subprocess time limit [s].
    render_probe_seconds: float = 60.0
    #: Largest |P P^T - I| entry of user-given machining-plane axes (chatter model).
    plane_orthonormal: float = 1e-9
    #: Relative step above a candidate limit K_c b at which stability is re-checked.
    chatter_limit_probe: float = 1e-7
    #: Arm eigenproblem: when lambda_min / lambda_max of ``K phi = lambda M phi`` falls
    #: below this, the highest modes are taken from the Cholesky-of-M form as well (the
    #: inverse form alone keeps them to ~eps / spread).
    eig_spread: float = 1e-10

    # ----- validation / diagnosis (issue 6)
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
    #: |correlation| of two candidates' unique signatures above which they are aliased.
    alias_correlation: float = 0.95
    #: Held-out RMS must fall below this fraction of the current model's held-out RMS.
    heldout_gain: float = 0.995
    #: Number of held-out folds (series assigned round-robin).
    cv_folds: int = 3
    #: Prior standard deviation of the baseline compliance scale factors [-] (weak).
    baseline_prior_sd: float = 1.0
    #: Relative finite-difference step of model sensitivities.
    fd_step: float = 1e-4
    #: Stiffness of "rigid" directions of a foundation spring [N/m, N m/rad].
    rigid_foundation: float = 1e13
    #: Largest plausible backlash / lost motion [rad].
    max_backlash: float = 5e-3
    #: Relative standard uncertainty of a measured natural frequency [-] (modal tests).
    freq_noise: float = 0.005
    #: Largest plausible link compliance factor vs the CAD flexible model [-].
    max_link_compliance: float = 5.0
    #: A winner is only a proxy of an aliased candidate that gains more on the residual
    #: when their unique signatures correlate above this [-] (then it is not accepted).
    proxy_correlation: float = 0.5
    #: Floor of a joint compliance scale factor during fits [-] (keeps stiffness > 0).
    min_compliance_scale: float = 1e-6


tol = Tolerances()
