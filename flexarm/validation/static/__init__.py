"""Static evidence: the generalised least-squares fit of load-deflection series, the
candidate effects and their screening, physical refits, shape-parameter searches, the
residual-structure tests and the misfit verdict, and the static comparison tables and
plots.

Sub-layer 2 of :mod:`flexarm.validation`: may import :mod:`~flexarm.validation.data`,
:mod:`~flexarm.validation.models` and :mod:`~flexarm.validation.tolerances`.
"""
