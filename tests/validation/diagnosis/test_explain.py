"""The one-sentence explanations: each fitted size with its standard error, in the unit a
user reads, written out by hand here."""

from __future__ import annotations

from types import SimpleNamespace as NS

import numpy as np
import pytest

from flexarm.validation.diagnosis.explain import explain


class _Effect:
    def __init__(self, **params):
        self.params = tuple(params.items())

    def get(self, name):
        return dict(self.params)[name]


def _problem():
    q = np.zeros((6, 6))
    q[:, 1] = np.radians([-30.0, -30.0, 0.0, 0.0, 45.0, 45.0])
    return NS(data=NS(q=q), ref=np.array([0, 2, 4]),
              arm=NS(joints=[NS(torsion=1e6)] * 6, chain=NS(n_joints=6)))


@pytest.mark.parametrize("kind, effect, theta, se, expected", [
    ("hysteresis", _Effect(radius=30.0), [2e-4], [1e-5],
     "joint 2 lost motion of 0.200 ± 0.010 mrad (friction torque 30 N m): unloading curves "
     "lie off the loading curves once the load reverses"),
    ("tilt", _Effect(), [2e-7], [1e-8],
     "joint 2 bearing tilt compliance 2e-07 ± 1e-08 rad/(N m) (stiffness 5e+06 N m/rad): "
     "deflections perpendicular to the joint-2 rotation are larger than the gear alone "
     "explains"),
    ("base", _Effect(), [4e-8], [2.5e-9],
     "base (foundation) tilt compliance 4e-08 ± 2.5e-09 rad/(N m) (stiffness 2.5e+07 N m/rad):"
     " the whole arm tips about the floor by the moment of the load about the base"),
    ("hardening", _Effect(threshold=150.0), [1e-6], [2e-8],
     "joint 2 stiffens with load: K1 = 0.50 K2 below 150 N m (extra compliance 1e-06 ± 2e-08 "
     "rad/(N m)): deflection grows faster than linear at low load and straightens above"),
    ("wrist", _Effect(c45=0.0, c46=0.0), [1e-7, 3e-7], [1e-8, 2e-8],
     "coupled wrist: joints 4-6 share compliance (c45 = 1e-07 ± 1e-08, c46 = 3e-07 ± 2e-08 "
     "rad/(N m)): a torque on one wrist joint also turns the others"),
    ("balancer", _Effect(kc=0.0, ks=2e5), [2e5], [1e4],
     "joint 2 gravity balancer: stiffness kc cos q2 + ks sin q2 in parallel with the gear "
     "(ks = 2e+05 ± 1e+04 N m/rad): joint 2's compliance changes with its angle across the "
     "series at q2 = -30, 0, 45 deg (not written to the robot file)"),
])
def test_sentence_of_each_candidate(kind, effect, theta, se, expected):
    cand = NS(kind=kind, joint=1, amplitudes={"c45": 1.0, "c46": 1.0}, label=kind)
    assert explain(_problem(), cand, effect, np.array(theta), np.array(se)) == expected
