"""Contact applications: IK along RAPID paths, the loaded circle test (LDBB) on the
E-model or the flexible arm (with gravity and nonlinear joints) and mode-coupling
chatter (thesis §2.4.4, §3.4.2, §4.2, §4.4).

The jobs behind the ``circle``, ``chatter`` and ``chatter-map`` commands are
:func:`run_circle`, :func:`run_chatter` and :func:`chatter_limits_map`.
"""

from ...robot.ik_path import PathIK, ik_conf, ik_path, rapid_conf, tool_frame
from .ball_bar import (
    CirclePrediction,
    CircleSetup,
    circle_setup,
    default_pivot,
    linear_solver,
    load_point_compliance,
    measured_deviation,
    predict_circle,
    rapid_circle,
    weak_directions,
)
from .chatter import ChatterResult, PlaneModel, analyse, cnc_model, plane_model, simulate
from .chatter_map import (
    ChatterMap,
    chatter_limits_map,
    chatter_map,
    critical_kcb,
    recommendation,
    worst_normal,
)
from .chatter_study import ChatterStudy, run_chatter, write_chatter_map
from .circle_data import static_circle_readings, synthetic_static_circle, write_circle_csv
from .circle_models import circle_joint_torques, nonlinear_solver
from .loaded_circle import CircleResult, CircleRun, run_circle
from .plane_batch import plane_axes_batched, plane_matrices

__all__ = [
    "ChatterMap", "ChatterResult", "ChatterStudy", "CirclePrediction", "CircleResult",
    "CircleRun", "CircleSetup", "PathIK", "PlaneModel", "analyse", "chatter_limits_map",
    "chatter_map", "circle_joint_torques", "circle_setup", "cnc_model", "critical_kcb",
    "default_pivot", "ik_conf", "ik_path", "linear_solver", "load_point_compliance",
    "measured_deviation", "nonlinear_solver", "plane_axes_batched", "plane_matrices",
    "plane_model", "predict_circle", "rapid_circle", "rapid_conf", "recommendation",
    "run_chatter", "run_circle", "simulate", "static_circle_readings",
    "synthetic_static_circle", "tool_frame", "weak_directions", "worst_normal",
    "write_chatter_map", "write_circle_csv",
]
