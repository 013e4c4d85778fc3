"""The arm as an Exudyn flexible-multibody model: floating-frame bodies from the
Craig-Bampton links, joint springs and proportional damping, an impulse test, a loaded
circle in the time domain, and the model written for use without flexarm (a script with
its matrices and mode bases beside it) or as a script that rebuilds it with flexarm.

Its sub-layers (``tests/test_layers.py``): ``bodies``, ``damping``, ``script`` and
``script_standalone`` import nothing of this package; ``model`` builds on the first two;
``impulse`` and ``path`` run the model, ``standalone`` writes it.  It may import the rest
of :mod:`flexarm.studies` (plots, contact), which never imports it back.  Exudyn itself
is imported only when a model is built (``pip install 'flexarm[mbs]'``).
"""
