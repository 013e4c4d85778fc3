"""The diagnosis with static and vibration data on the imported IRB 4600, over seeds
(``tests/validation/sweeps.py``; slow: ``python -m pytest -m slow -s`` prints each line).

* each cause outside the joint library (added mass, load-cell scale, reflector offset,
  anisotropic foundation) and a gravity balancer whose angle signature is in the data
  are named first on at least 19 of 20 seeds, and nothing wrong is accepted on any (a
  balancer accepted for one of the others counts as wrong);
* on the library's scenarios neither the new candidates nor a balancer are ever accepted
  (120 diagnoses), vibration data never turn a right answer into a wrong one, and they
  narrow the interval of the named effect's amplitude (median over the seeds both
  diagnoses got right);
* a channel of the shape file turned (node and direction drawn by the seed) is named on
  at least 19 of 20 seeds, with nothing accepted and no other residual structure left,
  and on the same seeds unturned no channel is named.
"""

from __future__ import annotations

import numpy as np
import pytest

from ..sweeps import (
    LIBRARY,
    NEW_CAUSES,
    channel_summary,
    channel_sweep,
    irb4600,
    summary,
    sweep,
)

pytestmark = pytest.mark.slow

#: Kinds none of the library's scenarios has: never accepted on them.
NEW_KINDS = ("mass", "loadcell", "reflector", "foundation", "balancer")


@pytest.fixture(scope="module")
def irb(tmp_path_factory):
    return irb4600(tmp_path_factory.mktemp("irb"))


@pytest.fixture(scope="module")
def irb_arm(irb):
    return irb[1]


@pytest.mark.parametrize("hidden", sorted(NEW_CAUSES))
def test_a_new_cause_is_named_first(irb_arm, hidden):
    name = NEW_CAUSES[hidden]
    out = sweep(irb_arm, hidden)
    print("\n" + summary(hidden, (name,), out))  # noqa: T201
    assert sum(bool(o.accepted) and o.accepted[0] == name for o in out) >= 19
    assert all(set(o.accepted) <= {name} for o in out)


@pytest.mark.parametrize("hidden", sorted(LIBRARY))
def test_vibration_data_never_spoil_a_right_answer(irb_arm, hidden):
    """20 seeds, static alone and with the modes: where the static diagnosis is right,
    the one with modal data is too, no new candidate is ever accepted, and the modes
    narrow the named effect's interval."""
    want = LIBRARY[hidden]
    static, modal = sweep(irb_arm, hidden, modal=False), sweep(irb_arm, hidden, modal=True)
    print("\nstatic       " + summary(hidden, want, static))  # noqa: T201
    print("static+modal " + summary(hidden, want, modal))  # noqa: T201
    for s, m in zip(static, modal, strict=True):
        if set(s.accepted) == set(want):
            assert set(m.accepted) == set(want), (s.seed, s.accepted, m.accepted)
        assert not any(a.split("_")[0] in NEW_KINDS for a in m.accepted), m
    both = [(s.rel_sd, m.rel_sd) for s, m in zip(static, modal, strict=True)
            if want and set(s.accepted) == set(m.accepted) == set(want)]
    if both:
        width_static, width_modal = np.median(both, axis=0)
        assert width_modal < width_static, (width_static, width_modal)


def test_a_reversed_channel_is_named_and_nothing_else(irb):
    robot, arm = irb
    turned, right = channel_sweep(robot, arm, turn=True), channel_sweep(robot, arm, turn=False)
    print("\n" + channel_summary(turned, right))  # noqa: T201
    assert sum(o.channels == (o.turned,) for o in turned) >= 19
    assert not any(o.accepted for o in turned + right)
    assert all(o.structures == ("reversed_channel",) for o in turned if o.channels)
    assert not any(o.channels for o in right)
