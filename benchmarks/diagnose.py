"""Wall time of a full diagnosis: 3 poses x 6 directions x 9 load levels.

Three cases: the E-model (target <= 10 s on 2 cores, with the measurement candidates,
the shape search of two effects on one joint and an unexplained misfit); the flexible
model (links as superelements, coarse 0.06 m mesh from the superelement cache; target
<= 3 min) as the model being diagnosed; and the link-flexibility search (E-model +
flexible candidate + 3 poses x 4 measured natural frequencies).  The flexible build is
timed separately (minutes on the first run, seconds from the cache).  Last, a static +
modal diagnosis on the IRB 4600 imported from its URDF (P1-P6 x 6 directions x 9 loads,
the first 6 modes at the 6 poses, 0.3 %) with a cause outside the joint library hidden
(target <= 30 s on 2 cores; ``--no-irb`` leaves it out).

Run: ``python benchmarks/diagnose.py``.  On a shared machine, ``OMP_NUM_THREADS=1``
avoids BLAS oversubscription (the many small solves gain nothing from threads).
"""

from __future__ import annotations

import time

from flexarm.assembly.emodel import emodel
from flexarm.robot.demo_arm import load_demo_robot
from flexarm.robot.effects import parse_effect
from flexarm.validation.data.load_plan import LabPlan, parse_dirs, parse_loads
from flexarm.validation.diagnosis.search import diagnose
from flexarm.validation.lab.faults import with_drift
from flexarm.validation.lab.modal_lab import virtual_modal
from flexarm.validation.lab.virtual_lab import virtual_lab

FLEX_MESH = 0.06


def main() -> None:
    robot = load_demo_robot()
    arm = emodel(robot, method="surface")
    plan = LabPlan({p: robot.pose(p) for p in ("P1", "P2", "P3")}, parse_loads("0:800:100"),
                   parse_dirs("x,y,z,-x,-y,-z"))
    for effects in (["backlash:j2=0.1mrad"], ["backlash:j2=0.1mrad", "base:k=2e7"],
                    ["tool:cxx=1e-7,cyy=1e-7,czz=3e-7"],
                    ["backlash:j2=0.2mrad", "hardening:j2=0.5,t=800Nm"], ["drift"]):
        drift = effects == ["drift"]
        data = virtual_lab(arm, plan, [] if drift else [parse_effect(e) for e in effects],
                           15e-6, seed=1)
        if drift:  # outside the library: 5 µm per reading
            data = with_drift(data, (3e-6, 0.0, 4e-6))
        t0 = time.perf_counter()
        dg = diagnose(arm, data, poses=robot.poses)
        dt = time.perf_counter() - t0
        names = [e.kind for e in dg.accepted]
        print(f"E-model, {len(data.series)} readings, hidden {effects}: {dt:.2f} s, "  # noqa: T201
              f"accepted {names}, unexplained misfit {dg.misfit.structures or 'none'}")
    from flexarm.assembly.build import BuildOptions
    from flexarm.assembly.flexible import flexible_arm

    t0 = time.perf_counter()
    flex = flexible_arm(robot, BuildOptions(mesh_size=FLEX_MESH, n_modes=4))
    print(f"flexible model build (mesh {FLEX_MESH} m): "  # noqa: T201
          f"{time.perf_counter() - t0:.1f} s")
    effects = [parse_effect("backlash:j2=0.1mrad")]
    data = virtual_lab(flex, plan, effects, 15e-6, seed=1)
    t0 = time.perf_counter()
    dg = diagnose(flex, data, poses=robot.poses)
    print(f"flexible model, {len(data.series)} readings, hidden backlash j2: "  # noqa: T201
          f"{time.perf_counter() - t0:.2f} s, accepted {[e.kind for e in dg.accepted]}")
    etets = emodel(robot, method="tets", mesh_size=FLEX_MESH)
    hidden = [parse_effect("links:c=1")]
    data = virtual_lab(etets, plan, hidden, 15e-6, seed=1, flexible=flex)
    modal = virtual_modal(etets, plan.poses, hidden, 4, seed=1, flexible=flex)
    t0 = time.perf_counter()
    dg = diagnose(etets, data, poses=robot.poses, modal=modal, flexible=flex)
    print(f"link flexibility search (E-model + flexible candidate + modal): "  # noqa: T201
          f"{time.perf_counter() - t0:.2f} s, accepted {[e.kind for e in dg.accepted]}")


def irb4600() -> None:
    """Static + modal diagnoses on the imported IRB 4600 (tests/validation/sweeps.py)."""
    import sys
    import tempfile
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from tests.validation.sweeps import NEW_CAUSES, irb4600, run_one

    with tempfile.TemporaryDirectory() as tmp:
        _, arm = irb4600(Path(tmp))
        for hidden in list(NEW_CAUSES) + ["backlash:j2=0.1mrad"]:
            o = run_one(arm, hidden, seed=1)
            print(f"IRB 4600 (URDF), 324 readings + 36 modes, hidden {hidden}: "  # noqa: T201
                  f"{o.seconds:.2f} s, accepted {list(o.accepted)}")


if __name__ == "__main__":
    import sys

    main()
    if "--no-irb" not in sys.argv:
        irb4600()
