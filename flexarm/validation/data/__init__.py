"""Measurement data: the data sets (static series, modal frequencies and shapes, FRFs,
loaded paths) as frozen dataclasses in SI units, their CSV and universal-file formats,
unit suffixes, measurement points, and static test plans.

Sub-layer 1 of :mod:`flexarm.validation`: imports the layers below ``validation`` and
:mod:`flexarm.validation.tolerances` only, never another validation sub-package.
"""
