"""The demo's measurement step: shipped lab data with a hidden effect, compared with the
nominal E-model, diagnosed, built into an updated robot file, and compared again.

Every stage is the validation API (:func:`~flexarm.validation.static.compare.compare_static`,
:func:`~flexarm.validation.diagnosis.search.diagnose`,
:func:`~flexarm.validation.diagnosis.history.robot_with_effects`) and the robot file formats; the
updated file carries its fitted nonlinear effects in ``Robot.effects``, so the second
comparison reads them back from the file rather than from the diagnosis.
"""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path
from typing import TYPE_CHECKING

from ..assembly.arm import ArmSpec, build_arm
from ..fe.files import file_digest
from ..robot import load_robot
from .demo_cache import demo_result
from .demo_results import Progress, StepResult

if TYPE_CHECKING:
    from ..validation.diagnosis.search import Diagnosis
    from ..validation.static.compare import Comparison

__all__ = ["LAB_DATA", "measurement_step"]

#: The shipped lab campaign: ``flexarm/data/lab/<LAB_DATA>``.
LAB_DATA = "lab_hidden_effect.csv"


def measurement_step(out: Path, progress: Progress) -> StepResult:
    """Compare -> diagnose -> update the robot file -> compare.

    Writes ``measurements.csv`` (a copy of the lab data), ``measurements_v0/`` and
    ``measurements_v1/`` (errors and plots before and after), ``diagnosis/`` (error
    history) and ``robot_v1.toml`` into ``out``.
    """
    from ..robot.formats import read, write
    from ..validation import read_measurements
    from ..validation.diagnosis.history import robot_with_effects, write_history
    from ..validation.diagnosis.search import diagnose
    from ..validation.static.compare import compare_static, write_report

    data_path = out / "measurements.csv"
    data_path.write_bytes((files("flexarm") / "data" / "lab" / LAB_DATA).read_bytes())
    robot = load_robot()
    arm = build_arm(robot, ArmSpec(mass="surface")).model
    data = read_measurements(data_path)
    progress("measurements: nominal model vs lab data, then diagnosis")
    before = compare_static(arm, data)
    write_report(out / "measurements_v0", before)
    # the costly part of the step: kept between runs, keyed by the data and the package
    dg = demo_result("diagnosis", lambda: diagnose(arm, data, poses=robot.poses),
                     file_digest(data_path))
    write_history(out / "diagnosis", dg, before.rms, float(before.problem.sigma.mean()),
                  f"{before.model} at {before.poses}")
    write(out / "robot_v1.toml", robot_with_effects(robot, arm, dg.final_effects))
    robot1 = read(out / "robot_v1.toml")
    after = compare_static(build_arm(robot1, ArmSpec(mass="surface")).model, data,
                           list(robot1.effects))
    write_report(out / "measurements_v1", after)
    figures = {
        "measurements_chi2_red_nominal": before.chi2_red,
        "measurements_chi2_red_fitted_baseline": dg.steps[0].chi2_red,
        "measurements_chi2_red_final": after.chi2_red,
        "measurements_rms_nominal_um": before.rms * 1e6,
        "measurements_rms_final_um": after.rms * 1e6,
    }
    return StepResult(_index_lines(before, dg, after), figures)


def _index_lines(before: Comparison, dg: Diagnosis, after: Comparison) -> list[str]:
    """The step's section of ``index.md`` from the comparisons ``before`` and ``after``
    the update and the diagnosis ``dg`` (RMS in µm)."""
    lo, hi = after.band
    return [
        "## Measurements: where the model fails and which effect is missing",
        "",
        "Lab data shipped with flexarm (a virtual laser-tracker campaign, 15 µm noise, "
        "3 poses × 6 load directions × 0–800 N) on an arm whose joint stiffnesses are ±30% off "
        "the nominal file and which has one hidden physical effect. The diagnosis never sees "
        "the truth file.",
        "",
        f"- Nominal model: χ²_red {before.chi2_red:.2f}, RMS {before.rms * 1e6:.1f} µm "
        "([errors and plots](measurements_v0/))",
        *[line for st in dg.steps for line in
          [f"- **Dropped**: {why}" for _, why in st.dropped]
          + ([f"- **Accepted**: {st.explanation}"] if st.accepted else [])],
        f"- Updated robot file [robot_v1.toml](robot_v1.toml): χ²_red {after.chi2_red:.3f} "
        f"(band {lo:.3f}–{hi:.3f}), RMS {after.rms * 1e6:.1f} µm "
        "([errors and plots](measurements_v1/))",
        "",
        "| model version | χ²_red | RMS fitted [µm] | RMS held-out [µm] |",
        "|---|---|---|---|",
        *[f"| {st.label} | {st.chi2_red:.3f} | {st.rms_fit * 1e6:.1f} "
          f"| {st.rms_heldout * 1e6:.1f} |" for st in dg.steps],
        "",
        "![error history](diagnosis/history.png)",
        "",
    ]
