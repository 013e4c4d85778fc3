"""Contact applications: IK along RAPID paths, the loaded circle test (LDBB) and
mode-coupling chatter (thesis §2.4.4, §3.4.2, §4.2, §4.4)."""

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
from .chatter_map import ChatterMap, chatter_map, critical_kcb, recommendation, worst_normal
from .ik_path import PathIK, ik_conf, ik_path, rapid_conf, tool_frame

__all__ = [
    "ChatterMap", "ChatterResult", "CirclePrediction", "CircleSetup", "PathIK", "PlaneModel",
    "analyse", "chatter_map", "circle_setup", "cnc_model", "critical_kcb", "default_pivot",
    "ik_conf", "ik_path", "linear_solver", "load_point_compliance", "measured_deviation",
    "plane_model", "predict_circle", "rapid_circle", "rapid_conf", "recommendation",
    "simulate", "tool_frame", "weak_directions", "worst_normal",
]
