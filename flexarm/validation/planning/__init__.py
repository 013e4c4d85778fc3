"""Test planning: the static series that best separate standing hypotheses, with the
expected Delta-BIC of each and a RAPID module that drives the robot to the poses.

Sub-layer 4 of :mod:`flexarm.validation`, beside ``lab`` and ``diagnosis``: may import
:mod:`~flexarm.validation.dynamic` and everything below it.
"""
