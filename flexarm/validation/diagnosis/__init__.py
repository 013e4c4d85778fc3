"""The diagnosis: fit the model to static and vibration evidence, rank the candidate
effects, accept, refit and repeat; its results and their text, the identifiability of the
baseline, one-line explanations, and the history of model versions with the robot file
that holds the accepted effects.

Sub-layer 4 of :mod:`flexarm.validation`, beside ``lab`` and ``planning``: the search
combines :mod:`~flexarm.validation.static` and :mod:`~flexarm.validation.dynamic`
evidence, so it sits above both, and may import everything below them.
"""
