"""Seed sweeps of the diagnosis with static and vibration data on the imported IRB 4600
(``../shared/data/irb4600``, as ``flexarm import-urdf`` writes it): the lab arm has the
usual +-30 % joint stiffness errors and one hidden cause; the data are static series at
P1-P6 x +-X+-Y+-Z, 0-800 N, 15 µm, plus the first 6 modes at the 6 poses, 0.3 %.
The reversed-channel sweep gives the modes with their shapes at the robot's default
points (x, y, z each, 2 % of each shape's peak) and turns one channel, drawn by the seed
among those that move (:func:`~flexarm.validation.dynamic.mac.moving_points`, 10 %).

:func:`sweep` runs one cause over seeds and counts what was named first, what was
accepted that is not the cause, and the verdict; the slow tests assert the counts and
``python -m tests.validation.sweeps`` prints them.
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from flexarm.robot.effects import parse_effect
from flexarm.validation.data.load_plan import LabPlan, parse_dirs, parse_loads
from flexarm.validation.diagnosis.search import diagnose
from flexarm.validation.dynamic.mac import moving_points
from flexarm.validation.dynamic.shapes import default_points
from flexarm.validation.lab.modal_lab import virtual_modal, virtual_shapes
from flexarm.validation.lab.virtual_lab import virtual_lab

from .helpers import PERTURB

SIGMA, FREQ_NOISE, SHAPE_NOISE = 15e-6, 0.003, 0.02
#: Poses [deg]: the thesis's P1-P3 and three more across the workspace.
POSES_DEG = {
    "P1": (0, 52, -19, 12, -15, -11),
    "P2": (0, 0, 66, 0, -66, 0),
    "P3": (0, 32, 20, 101, -98, -35),
    "P4": (30, 30, 0, 45, 40, 60),
    "P5": (-30, 10, 20, -60, -50, 30),
    "P6": (15, 60, -40, 90, 30, -45),
}
#: The new causes: hidden effect -> the candidate that names it.
NEW_CAUSES = {
    "mass:l3=20kg": "mass_l3",
    "loadcell:s=0.03": "loadcell",
    "reflector:ox=30mm": "reflector",
    "foundation:kx=1e7": "foundation",
    # a balancer on joint 2 of 1.0-1.4 MN m/rad over the poses' q2 (0-60 deg), a quarter to
    # a third of the gear's 4.3 MN m/rad: joint 2's compliance swings by 7 % with the angle,
    # a signature no joint scale mimics
    "balancer:j2=1e6,s=5e5": "balancer_j2",
}
#: The library's scenarios (hidden effects -> the candidates that name them).
LIBRARY = {
    "": (),
    "backlash:j2=0.1mrad": ("backlash_j2",),
    "base:k=1e7": ("base",),
    "tool:cxx=1e-7,cyy=1e-7,czz=3e-7": ("tool",),
    "wrist:c45=0.5": ("wrist",),
    "hardening:j2=0.5,t=2000Nm": ("hardening_j2",),
}


def irb4600(folder: Path):
    """(robot, E-model) of the IRB 4600 imported into ``folder``."""
    from flexarm.assembly.emodel import emodel
    from flexarm.robot.formats import read

    from ..irb4600 import import_irb

    toml, _, _ = import_irb(Path(folder))
    robot = read(toml)
    return robot, emodel(robot, method="surface")


@dataclass(frozen=True)
class Outcome:
    """One diagnosis of a sweep."""

    seed: int
    accepted: tuple  # candidate names, in order
    unexplained: bool
    seconds: float
    rel_sd: float = float("nan")  # sd / |value| of the first accepted amplitude
    channels: tuple = ()  # the channels named reversed ("channel node 601 y")
    turned: str = ""  # the channel the lab turned, in the same words
    structures: tuple = ()  # what the verdict found in the final model's residual


def _lab(arm, hidden: str, seed: int):
    """(poses, effects, static data) of the lab arm with ``hidden`` (``;``-separated)."""
    poses = {p: np.radians(q) for p, q in POSES_DEG.items()}
    eff = ([parse_effect(f"stiffness:j{j + 1}={s}") for j, s in enumerate(PERTURB)]
           + [parse_effect(h) for h in hidden.split(";") if h])
    plan = LabPlan(poses, parse_loads("0:800:100"), parse_dirs("x,y,z,-x,-y,-z"))
    return poses, eff, virtual_lab(arm, plan, eff, SIGMA, seed)


def run_one(arm, hidden: str, seed: int, modal: bool = True) -> Outcome:
    """Lab data of ``hidden`` (``;``-separated effects) on ``arm`` and their diagnosis."""
    poses, eff, data = _lab(arm, hidden, seed)
    m = virtual_modal(arm, poses, eff, n_modes=6, freq_noise=FREQ_NOISE, seed=seed) \
        if modal else None
    t = time.perf_counter()
    dg = diagnose(arm, data, SIGMA, modal=m, freq_noise=FREQ_NOISE, heldout=False)
    return _outcome(dg, seed, time.perf_counter() - t)


def run_channel(robot, arm, seed: int, turn: bool = True) -> Outcome:
    """Static data and the modes with shapes of the lab arm (nothing hidden) with one
    moving channel turned (``turn``; drawn by ``seed``), and their diagnosis."""
    poses, eff, data = _lab(arm, "", seed)
    pts = default_points(robot)
    shapes = virtual_shapes(arm, poses, pts, eff, n_modes=6, freq_noise=FREQ_NOISE,
                            shape_noise=SHAPE_NOISE, seed=seed)
    moving = np.flatnonzero(moving_points(shapes.shapes, np.arange(shapes.n_dofs), 0.1))
    i = int(np.random.default_rng((seed, 1)).choice(moving))
    turned = f"channel node {int(shapes.nodes[i])} {shapes.dirs[i]}"
    if turn:
        S = np.array(shapes.shapes)
        S[:, i] *= -1
        shapes = replace(shapes, shapes=S)
    t = time.perf_counter()
    dg = diagnose(arm, data, SIGMA, modal=shapes, freq_noise=FREQ_NOISE, points=pts,
                  shape_noise=SHAPE_NOISE, heldout=False)
    out = _outcome(dg, seed, time.perf_counter() - t)
    return replace(out, turned=turned if turn else "", structures=dg.misfit.structures,
                   channels=tuple(c.split(" looks")[0] for c in dg.misfit.channels))


def _outcome(dg, seed: int, seconds: float) -> Outcome:
    names = dg.named
    first = next((s.winner for s in dg.steps if s.accepted and s.winner.name in names), None)
    rel = float("nan")
    if first is not None and first.params:
        value, sd = next(iter(first.params.values()))
        rel = sd / abs(value) if value else float("nan")
    return Outcome(seed, names, dg.unexplained, seconds, rel)


def sweep(arm, hidden: str, seeds=range(20), modal: bool = True,
          verbose: bool = False) -> list[Outcome]:
    out = []
    for s in seeds:
        out.append(run_one(arm, hidden, s, modal))
        if verbose:  # a sweep runs for long: each diagnosis as it ends, on stderr
            print(f"  {hidden or 'nothing'} seed {s}: {', '.join(out[-1].accepted) or '-'}"  # noqa: T201
                  f" ({out[-1].seconds:.0f} s)", file=sys.stderr, flush=True)
    return out


def summary(hidden: str, want: tuple, outcomes: list[Outcome]) -> str:
    first = sum(bool(o.accepted) and o.accepted[0] in want for o in outcomes) if want else \
        sum(not o.accepted for o in outcomes)
    wrong = sum(any(a not in want for a in o.accepted) for o in outcomes)
    secs = np.mean([o.seconds for o in outcomes])
    rel = [o.rel_sd for o in outcomes if np.isfinite(o.rel_sd)]
    width = f", median interval ±{100 * np.median(rel):.1f} %" if rel else ""
    return (f"{hidden or 'nothing hidden':34s} named first {first}/{len(outcomes)}, something "
            f"wrong accepted {wrong}/{len(outcomes)}, unexplained "
            f"{sum(o.unexplained for o in outcomes)}{width}, {secs:.1f} s per diagnosis")


def spoiled(want: tuple, static: list[Outcome], modal: list[Outcome]) -> str:
    """How many right static answers the vibration data turned wrong, seed by seed, and
    the named effect's median interval without and with them (seeds both got right)."""
    right = [(s, m) for s, m in zip(static, modal, strict=True) if set(s.accepted) == set(want)]
    bad = sum(set(m.accepted) != set(want) for _, m in right)
    both = [(s.rel_sd, m.rel_sd) for s, m in right if want and set(m.accepted) == set(want)]
    width = (" median interval ±{:.1f} % -> ±{:.1f} %".format(*(100 * np.median(both, axis=0)))
             if both else "")
    return f"modal data spoiled {bad}/{len(right)} right static answers;{width}"


def channel_sweep(robot, arm, seeds=range(20), turn: bool = True,
                  verbose: bool = False) -> list[Outcome]:
    """:func:`run_channel` over ``seeds`` (each diagnosis on stderr with ``verbose``)."""
    out = []
    for s in seeds:
        out.append(run_channel(robot, arm, s, turn))
        if verbose:
            o = out[-1]
            print(f"  {o.turned or 'no channel'} turned, seed {s}: named "  # noqa: T201
                  f"{', '.join(o.channels) or '-'}; accepted {', '.join(o.accepted) or '-'}"
                  f" ({o.seconds:.0f} s)", file=sys.stderr, flush=True)
    return out


def channel_summary(turned: list[Outcome], right: list[Outcome]) -> str:
    """The reversed-channel sweep in one line: the turned channel named (alone), anything
    accepted (nothing is hidden), a residual structure besides the channel, and a channel
    named on the same seeds unturned."""
    named = sum(o.channels == (o.turned,) for o in turned)
    wrong = sum(bool(o.accepted) for o in turned)
    more = sum(bool(set(o.structures) - {"reversed_channel"}) for o in turned)
    false = sum(bool(o.channels) for o in right)
    secs = np.mean([o.seconds for o in turned + right])
    return (f"{'reversed channel':34s} named {named}/{len(turned)}, something wrong accepted "
            f"{wrong}/{len(turned)}, another structure left {more}/{len(turned)}; unturned: "
            f"a channel named {false}/{len(right)}, something accepted "
            f"{sum(bool(o.accepted) for o in right)}/{len(right)}, unexplained "
            f"{sum(o.unexplained for o in right)}, {secs:.1f} s per diagnosis")


if __name__ == "__main__":  # python -m tests.validation.sweeps [N [new|library|channel|CAUSE]]
    import tempfile

    n = int(sys.argv[1]) if len(sys.argv) > 1 else 20
    # "new", "library" or "channel": one group of the sweep; any other text: the causes
    # containing it
    only = sys.argv[2] if len(sys.argv) > 2 else ""
    with tempfile.TemporaryDirectory() as tmp:
        robot, arm = irb4600(Path(tmp))
        for hidden, name in NEW_CAUSES.items():
            if only == "new" or (only != "library" and only in hidden):
                print(summary(hidden, (name,), sweep(arm, hidden, range(n), verbose=True)),  # noqa: T201
                      flush=True)
        for hidden, names in LIBRARY.items():
            if only == "new" or (only not in ("", "library") and only not in hidden):
                continue
            both = []
            for modal in (False, True):
                both.append(sweep(arm, hidden, range(n), modal, verbose=True))
                print(("static+modal " if modal else "static       ")  # noqa: T201
                      + summary(hidden, names, both[-1]), flush=True)
            print("             " + spoiled(names, *both), flush=True)  # noqa: T201
        if only in ("", "channel"):
            print(channel_summary(channel_sweep(robot, arm, range(n), True, True),  # noqa: T201
                                  channel_sweep(robot, arm, range(n), False, True)),
                  flush=True)
