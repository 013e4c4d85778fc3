"""The keys a robot TOML may hold, table by table, and the checked access to its tables:
a misspelt key is an error with a did-you-mean, never silently dropped."""

from __future__ import annotations

import difflib

__all__ = ["MODEL_KEYS", "JOINT_KEYS", "LINK_KEYS", "TOP_KEYS", "OPTION_KEYS", "BASE_KEYS",
           "TOOL_KEYS", "WRIST_KEYS", "LUMPED_KEYS", "REGION_KEYS", "MATERIAL_KEYS",
           "check_keys", "table", "tables"]

MODEL_KEYS = {"torsion", "tilt", "tilt2", "radial", "axial", "damping_ratio", "rayleigh",
               "placeholder"}
JOINT_KEYS = {"name", "parent", "child", "origin", "rpy_deg", "axis", "limits_deg",
               "gear_ratio", "model", "emodel"}
LINK_KEYS = {"name", "mesh", "units", "material", "lumped", "regions", "volume_meshes"}
TOP_KEYS = {"format_version", "name", "model", "base", "tool", "poses", "wrist", "links",
             "joints", "nonlinear", "modal_damping", "effects"}
OPTION_KEYS = {"element_order", "mesh_size", "cb_modes", "mesher"}
BASE_KEYS = {"support", "stiffness", "damping_ratio"}
TOOL_KEYS = {"xyz", "rpy_deg", "link"}
WRIST_KEYS = {"coupling", "stiffness"}
LUMPED_KEYS = {"name", "mass", "position", "inertia"}
REGION_KEYS = {"center", "axis", "r_min", "r_max", "half_width", "coupling", "review"}
MATERIAL_KEYS = {"E", "nu", "rho", "name"}


def check_keys(table: dict, allowed: set, where: str) -> None:
    """A misspelt key is an error (a dropped one would silently change the model).

    Examples
    --------
    >>> check_keys({"xzy": [0, 0, 0.1]}, TOOL_KEYS, "tool")
    Traceback (most recent call last):
    ...
    ValueError: tool: unknown key 'xzy' (did you mean 'xyz'?)
    """
    extra = sorted(set(table) - allowed)
    if extra:
        near = difflib.get_close_matches(extra[0], sorted(allowed), n=1, cutoff=0.6)
        hint = f"did you mean '{near[0]}'?" if near else f"allowed: {sorted(allowed)}"
        raise ValueError(f"{where}: unknown key '{extra[0]}' ({hint})")


def table(data: dict, key: str, where: str, allowed: set | None = None) -> dict:
    """The table ``data[key]`` (empty when absent), its keys checked against ``allowed``."""
    value = data.get(key, {})
    if not isinstance(value, dict):
        raise ValueError(f"{where}{key} must be a table, got {value!r}")
    if allowed is not None:
        check_keys(value, allowed, f"{where}{key}")
    return value


def tables(data: dict, key: str, where: str = "") -> list[dict]:
    """The array of tables ``[[key]]`` (empty when absent)."""
    value = data.get(key, [])
    if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
        raise ValueError(f"{where}{key} must be an array of tables ([[{key}]]), got {value!r}")
    return value
