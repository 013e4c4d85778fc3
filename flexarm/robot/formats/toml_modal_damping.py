"""The ``[modal_damping]`` table of a robot TOML: modal damping ratios identified at
named poses, one sub-table per pose::

    [modal_damping.P1]            # a pose of [poses]
    freq_hz = [8.48, 14.8, 39.9]  # identified natural frequencies [Hz]
    zeta = [0.021, 0.018, 0.025]  # their damping ratios [-]

``flexarm fit-damping modal.csv --method modal`` writes it; the FRF at that pose uses
these ratios for the model modes they match by frequency
(:mod:`flexarm.validation.dynamic.pose_damping`), the joints' damping everywhere else.
"""

from __future__ import annotations

__all__ = ["MODAL_DAMPING_KEYS", "modal_damping_from_table", "modal_damping_table"]

#: The keys of one pose's sub-table.
MODAL_DAMPING_KEYS = {"freq_hz", "zeta"}


def _numbers(value, key: str) -> tuple[float, ...]:
    if not isinstance(value, list) or not all(isinstance(v, int | float) for v in value):
        raise ValueError(f"{key} must be a list of numbers, got {value!r}")
    return tuple(float(v) for v in value)


def modal_damping_from_table(table: dict) -> dict:
    """``{pose: (freq_hz, zeta)}`` of a parsed ``[modal_damping]`` table (keys checked;
    the values are checked against the poses by the robot's validation).

    Examples
    --------
    >>> modal_damping_from_table({"P1": {"freq_hz": [8.5, 15], "zeta": [0.02, 0.03]}})
    {'P1': ((8.5, 15.0), (0.02, 0.03))}
    >>> modal_damping_from_table({"P1": {"freq": [8.5]}})
    Traceback (most recent call last):
    ...
    ValueError: modal_damping.P1: unknown key 'freq' (did you mean 'freq_hz'?)
    """
    from .toml_keys import check_keys

    out = {}
    for pose, sub in table.items():
        where = f"modal_damping.{pose}"
        if not isinstance(sub, dict):
            raise ValueError(f"{where} must be a table with freq_hz and zeta, got {sub!r}")
        check_keys(sub, MODAL_DAMPING_KEYS, where)
        missing = sorted(MODAL_DAMPING_KEYS - set(sub))
        if missing:
            raise ValueError(f"{where}: missing '{missing[0]}'")
        out[str(pose)] = (_numbers(sub["freq_hz"], f"{where}.freq_hz"),
                          _numbers(sub["zeta"], f"{where}.zeta"))
    return out


def modal_damping_table(modal_damping: dict) -> dict:
    """The ``[modal_damping]`` table of ``robot.modal_damping`` (empty when none).

    Examples
    --------
    >>> modal_damping_table({"P1": ((8.5,), (0.02,))})
    {'P1': {'freq_hz': [8.5], 'zeta': [0.02]}}
    """
    return {pose: {"freq_hz": [float(f) for f in freq], "zeta": [float(z) for z in zeta]}
            for pose, (freq, zeta) in modal_damping.items()}
