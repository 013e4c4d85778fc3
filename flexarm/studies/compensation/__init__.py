"""Deflection-compensated robot programs: a program (RAPID module or CSV of poses), a
process force and an (identified) robot model in, the program whose loaded tool lands on
the programmed path out, and the virtual lab that runs it.

Sub-packages by job, lowest first (their order is the sub-layer table of
``tests/test_layers.py``; each ``__init__`` says what it may import):

* :mod:`.solve` -- the physics: process forces, batched IK, gravity sag, the loaded arm,
  the fixed point, the limits of a static shift, a loaded program's path;
* :mod:`.program` -- programs in and out: procedures as the arm runs them, a CSV of poses
  as a program (:func:`~.path_in.read_program`, the one reader of ``compensate``, ``lab``
  and ``compare``), rewriting robtargets, splitting motions, RAPID/KRL/CSV output;
* :mod:`.result` (:class:`CompensationResult`) and :mod:`.workflow` (:func:`compensate`);
* :mod:`.lab` -- the lab loop: the virtual lab running a program, a measured path against
  the program, the loop's error history;

and :mod:`.plots` (the pictures, importing nothing of the package).

A member of the flat floor of :mod:`flexarm.studies`: it may import
:mod:`flexarm.studies.contact` and the layers below (:mod:`flexarm.validation` for the
measurement file formats).
"""

from . import lab, program, solve
from .lab import *  # noqa: F403 (each sub-package's __all__, as skfem re-exports)
from .program import *  # noqa: F403
from .result import CompensationResult, TargetShift
from .solve import *  # noqa: F403
from .workflow import compensate

__all__ = ["CompensationResult", "TargetShift", "compensate"]
__all__ += solve.__all__
__all__ += program.__all__
__all__ += lab.__all__
