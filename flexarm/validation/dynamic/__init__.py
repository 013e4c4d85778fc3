"""Vibration evidence: modal frequencies and shapes of the model at measured poses, their
pairing with measured modes (frequency window and MAC), modal and FRF comparisons,
modal identification from FRFs (EMA), and joint damping fits and checks.

Sub-layer 3 of :mod:`flexarm.validation`: may import :mod:`~flexarm.validation.static`
(the modal observations join its GLS problem), :mod:`~flexarm.validation.data`,
:mod:`~flexarm.validation.models` and :mod:`~flexarm.validation.tolerances`.
"""
