"""The virtual lab: measurement files (static series, modal data, universal files) from a
model with hidden effects and noise, and measurement faults that no candidate models.

Sub-layer 4 of :mod:`flexarm.validation`, beside ``planning`` and ``diagnosis`` (none of
the three imports another): may import :mod:`~flexarm.validation.dynamic` and everything
below it.
"""
