"""Hostile numbers for :mod:`tests.cli.test_hostile`'s table: every typed number of the
command line (``nan``, ``inf``, ``1e30``, a wrong sign, a missing or wrong unit, an empty
list, a count of zero) is refused by its option's type with one line naming the option
and the value, exit code 2, before any work.

Imported by ``test_hostile.py`` after its helpers, whose :func:`case` registers each one.
"""

from __future__ import annotations

import re

from .test_hostile import box_vtu, case


def _option(id_, argv, option, value, why, absent=(), **kw):
    """``argv`` (a list, or ``build(tmp) -> list``) refused with the line
    ``OPTION VALUE: WHY`` (``why`` a regex; the rest literal), without argparse's usage."""
    build = argv if callable(argv) else (lambda t, argv=argv: list(argv))
    case(id_, build, r"^flexarm [\w-]+: error: " + re.escape(f"{option} {value}: ") + why,
         absent=absent, **kw)


NOT_FINITE = "not a finite number"

# compliance --force [N]: bare newtons, a force unit accepted, finite, > 0 and <= 1e6 N.
_FORCE = re.escape("must be > 0 and <= 1e6 N")
for id_, value, why in [
    ("force-nan", "nan", NOT_FINITE),
    ("force-inf", "inf", NOT_FINITE),
    ("force-minus-inf", "-inf", NOT_FINITE),
    ("force-1e30", "1e30", _FORCE),
    ("force-1e999", "1e999", _FORCE),
    ("force-1e30-kN", "1e30kN", _FORCE),
    ("force-negative", "-800", _FORCE),
    ("force-zero", "0", _FORCE),
    ("force-moment-unit", "800Nm", re.escape("unknown force unit 'Nm' (accepted: N, kN)")),
    ("force-text", "lots", "not a number"),
    ("force-hex", "0x10", "unknown force unit 'x10'"),
]:
    _option(f"number-{id_}", ["compliance", "--force", value], "--force", value, why)
_option("number-force-empty", ["compliance", "--force", ""], "--force", "''", "empty")

# circle: --loads [N] a comma list, --pivot x,y,z [mm], --step [mm].
for id_, value, why in [
    ("loads-nan", "0,nan", NOT_FINITE),
    ("loads-1e30", "0,1e30", re.escape("outside 0..1e5 N")),
    ("loads-negative", "0,-200", re.escape("outside 0..1e5 N")),
    ("loads-text", "0,lots", "not a number"),
]:
    _option(f"number-circle-{id_}", ["circle", "--loads", value], "--loads",
            value.split(",")[-1], why)
for id_, value in [("loads-empty", ""), ("loads-empty-entry", "0,,800")]:
    _option(f"number-circle-{id_}", ["circle", "--loads", value], "--loads", repr(value),
            "expected comma-separated values, none empty")
_option("number-circle-pivot-two", ["circle", "--pivot", "100,200"], "--pivot", "100,200",
        "expected 3 values, got 2")
_option("number-circle-pivot-inf", ["circle", "--pivot", "0,0,inf"], "--pivot", "inf",
        NOT_FINITE)
_option("number-circle-pivot-far", ["circle", "--pivot", "0,0,1e9"], "--pivot", "1e9",
        re.escape("outside -1e4..1e4 mm"))
for value in ("0", "-2", "5m"):
    _option(f"number-circle-step-{value}", ["circle", "--step", value], "--step", value,
            re.escape("must be > 0 and <= 1000 mm"))
case("number-circle-effect-joint-count",
     lambda t: ["circle", "--effect", "backlash:j9=1mrad"],
     re.escape("--effect 'backlash:j9=1mrad': joint 9 outside 1..6"))

# chatter: --kc [N/m] (a negative value is a value, refused by its range), angles [deg].
_KC = re.escape("outside 0..1e10 N/m")
for id_, argv, value, why in [
    ("kc-1e300", ["--kc", "1e300"], "1e300", _KC),
    ("kc-negative", ["--kc", "-5e5"], "-5e5", _KC),
    ("kc-negative-equals", ["--kc=-5e5"], "-5e5", _KC),
    ("kc-nan", ["--kc", "nan"], "nan", NOT_FINITE),
    ("kc-force-unit", ["--kc", "2e6N"], "2e6N", "unknown stiffness unit 'N'"),
    ("kc-N-per-um", ["--kc", "1e5N/um"], "1e5N/um", _KC),
]:
    _option(f"number-chatter-{id_}", ["chatter", *argv], "--kc", value, why)
for option, value, why in [
    ("--dir", "-1e999", re.escape("outside -360..360 deg")),
    ("--normal", "nan", NOT_FINITE),
    ("--normal", "7rad", re.escape("outside -360..360 deg")),
    ("--duration", "0", re.escape("must be > 0 and <= 100 s")),
    ("--duration", "1e9", re.escape("must be > 0 and <= 100 s")),
    ("--cnc-stiffness", "-5e7", re.escape("must be > 0 and <= 1e12 N/m")),
]:
    _option(f"number-chatter{option}-{value}", ["chatter", option, value], option, value, why)
_option("number-chatter-map-n-1", ["chatter-map", "--n", "1"], "--n", "1",
        re.escape("outside 2..200"))


# lab: lengths need a unit; effects checked for units, signs and ranges.
def _lab(*argv):
    return lambda t: ["lab", *argv, "-o", str(t / "s.csv")]


_NOISE = re.escape("outside 0..1e4 um")
for id_, option, value, why in [
    ("noise-bare", "--noise", "25", re.escape("give a unit, e.g. 25um")),
    ("noise-negative", "--noise", "-25um", _NOISE),
    ("noise-huge", "--noise", "1m", _NOISE),
    ("noise-nan", "--noise", "nan", NOT_FINITE),
    ("noise-angle-unit", "--noise", "25mrad", "unknown length unit 'mrad'"),
    ("ref-noise-bare", "--ref-noise", "45", re.escape("give a unit, e.g. 45um")),
    ("ref-noise-negative", "--ref-noise", "-45um", _NOISE),
    ("freq-noise-negative", "--freq-noise", "-1", re.escape("outside 0..100 %")),
    ("seed-negative", "--seed", "-1", re.escape("outside 0..4294967295")),
    ("n-modes-zero", "--n-modes", "0", re.escape("outside 1..100")),
    ("loads-reversed", "--loads", "800:0:100", "need start <= stop and step > 0"),
    ("loads-tiny-step", "--loads", "0:800:1e-9", "8e11 levels, at most 1000"),
    ("loads-inf", "--loads", "0:inf:100", NOT_FINITE),
    ("loads-subnormal-step", "--loads", "0:800:1e-320", "inf levels, at most 1000"),
    ("frf-band-reversed", "--frf-band", "300:0.25", "expected LO < HI"),
    ("flex-mesh-zero", "--flex-mesh", "0", re.escape("must be > 0 and <= 2 m")),
]:
    shown = "inf" if id_ == "loads-inf" else value  # a level names its own text
    _option(f"number-lab-{id_}", _lab(option, value), option, shown, why, absent=("s.csv",))
_option("number-lab-noise-equals", _lab("--noise=-25um"), "--noise", "-25um", _NOISE,
        absent=("s.csv",))
for id_, spec, why in [
    ("backlash-negative", "backlash:j2=-0.1mrad",
     "backlash width -0.1mrad: " + re.escape("must be > 0 and <= 100 mrad")),
    ("backlash-bare", "backlash:j2=0.1", "backlash width 0.1: give a unit, e.g. 0.1mrad"),
    ("backlash-1e6mrad", "backlash:j2=1e6mrad", "backlash width 1e6mrad: must be"),
    ("backlash-nan", "backlash:j2=nanmrad", "backlash width nanmrad: not a number"),
    ("hysteresis-negative", "hysteresis:j2=-0.1mrad", "hysteresis lost motion -0.1mrad"),
    ("hysteresis-radius", "hysteresis:j2=0.1mrad,r=-300Nm", "hysteresis radius -300Nm"),
    ("hardening-ratio", "hardening:j2=2", re.escape("hardening ratio K1/K2 2: must be > 0")),
    ("stiffness-zero", "stiffness:j2=0", "torsion stiffness factor 0: must be > 0"),
    ("frame-bare", "frame:rz=1.5", "frame rotation rz 1.5: give a unit, e.g. 1.5deg"),
    ("reflector-bare", "reflector:ox=30", "reflector offset ox 30: give a unit"),
    ("mass-negative", "mass:l3=-20kg", "added mass -20kg: must be > 0"),
    ("tilt-nan", "tilt:j1=nan", "tilt stiffness nan: " + NOT_FINITE),
    ("wrist-2", "wrist:c45=2", re.escape("wrist correlation c45 2: must be > -1 and < 1")),
    ("tool-negative", "tool:cxx=-1e-7", "tool compliance cxx -1e-7: outside 0..0.001 m/N"),
    ("base-unit", "base:k=2e7N", "foundation tilt stiffness 2e7N: unknown torsional"),
]:
    case(f"number-lab-effect-{id_}", _lab("--effect", spec),
         re.escape(f"flexarm lab: error: --effect '{spec}': ") + why, absent=("s.csv",))

# part commands: counts and lengths.
for id_, argv, option, value, why in [
    ("modal-n-zero", ["modal", "m.vtu", "-n", "0"], "-n/--modes", "0", "outside 1..100000"),
    ("modal-n-negative", ["modal", "m.vtu", "-n", "-3"], "-n/--modes", "-3", "outside 1"),
    ("modal-n-fraction", ["modal", "m.vtu", "-n", "2.5"], "-n/--modes", "2.5",
     "not a whole number"),
    ("modal-n-exponent", ["modal", "m.vtu", "-n", "1e3"], "-n/--modes", "1e3",
     "not a whole number"),
    ("show-frames-zero", ["show", "se.h5", "--frames", "0"], "--frames", "0", "outside 2..200"),
    ("show-frames-huge", ["show", "se.h5", "--frames", "100000"], "--frames", "100000",
     "outside 2..200"),
    ("show-mode-zero", ["show", "se.h5", "--mode", "0"], "--mode", "0", "outside 1"),
    ("show-max-displacement", ["show", "se.h5", "--mode", "1", "--max-displacement", "-1"],
     "--max-displacement", "-1", "must be > 0"),
    ("mesh-size-nan", ["mesh", "b.stl", "--size", "nan", "-o", "o.vtu"], "--size", "nan",
     NOT_FINITE),
    ("mesh-size-1e9", ["mesh", "b.stl", "--size", "1e9", "-o", "o.vtu"], "--size", "1e9",
     "must be > 0 and <= 10 m"),
    ("reduce-modes-negative", ["reduce", "m.vtu", "--modes", "-1", "-o", "se.h5"], "--modes",
     "-1", "outside 0..10000"),
    ("reduce-masters-zero", ["reduce", "m.vtu", "--masters", "0", "-o", "se.h5"], "--masters",
     "0", "outside 1"),
    ("study-part-modes", ["study-part", "--modes", "0,x"], "--modes", "x",
     "not a whole number"),
]:
    _option(f"number-{id_}", argv, option, value, re.escape(why))
case("number-modal-n-above-dof", lambda t: ["modal", str(box_vtu(t)), "-n", "100000"],
     r"-n/--modes 100000: .*bar\.vtu has \d+ free DOF, at most \d+ elastic modes",
     capped=True)

# arm commands.
for id_, argv, option, value, why in [
    ("frf-fmax-zero", ["frf", "--fmax", "0"], "--fmax", "0", "must be > 0 and <= 1e5 Hz"),
    ("frf-fmax-inf", ["frf", "--fmax", "inf"], "--fmax", "inf", NOT_FINITE),
    ("map-n-1", ["map", "--n", "1"], "--n", "1", "outside 2..1000"),
    ("modes-n-zero", ["modes", "-n", "0"], "-n/--n-modes", "0", "outside 1..100000"),
    ("import-urdf-mass", ["import-urdf", "r.urdf", "-o", "r.toml", "--total-mass", "-425"],
     "--total-mass", "-425", "must be > 0 and <= 1e5 kg"),
    ("import-urdf-wall", ["import-urdf", "r.urdf", "-o", "r.toml", "--wall", "-8mm"],
     "--wall", "-8mm", "must be > 0 and <= 1 m"),
    ("import-urdf-wall-word", ["import-urdf", "r.urdf", "-o", "r.toml", "--wall", "thin"],
     "--wall", "thin", "not a number"),
    ("mesh-size-zero", ["compliance", "--mesh-size", "0"], "--mesh-size", "0",
     "must be > 0 and <= 2 m"),
    ("build-modes-negative", ["build", "--modes", "-1"], "--modes", "-1", "outside 0..500"),
    ("study-sizes-negative", ["study", "--sizes", "0.03,-0.01"], "--sizes", "-0.01",
     "must be > 0 and <= 2 m"),
    ("study-modes-negative", ["study", "--modes", "5,-1"], "--modes", "-1", "outside 0..500"),
    ("show-arm-amplitude", ["show-arm", "--amplitude", "5"], "--amplitude", "5",
     "must be > 0 and <= 1"),
    ("export-arm-n-modes", ["export-arm", "--n-modes", "0", "-o", "a.npz"], "--n-modes", "0",
     "outside 1..100000"),
    ("impulse-direction-two", ["exudyn-impulse", "--direction", "1,1"], "--direction", "1,1",
     "expected 3 values, got 2"),
    ("impulse-dt-zero", ["exudyn-impulse", "--dt", "0"], "--dt", "0", "must be > 0 and <= 1 s"),
    ("exudyn-circle-speed", ["exudyn-circle", "--speed", "0"], "--speed", "0",
     "must be > 0 and <= 1e4 mm/s"),
    ("exudyn-circle-force", ["exudyn-circle", "--force", "-200"], "--force", "-200",
     "outside 0..1e5 N"),
    ("demo-jobs-zero", ["demo", "-j", "0"], "-j/--jobs", "0", "outside 1..64"),
]:
    _option(f"number-{id_}", argv, option, value, re.escape(why))

# measurements and their analyses.
for id_, argv, option, value, why in [
    ("check-damping-sigma", ["check-damping", "m.csv", "--sigma-pct", "100"], "--sigma-pct",
     "100", "must be > 0 and < 100 %"),
    ("check-damping-alpha", ["check-damping", "m.csv", "--alpha", "1"], "--alpha", "1",
     "must be > 0 and < 1"),
    ("fit-damping-max-hz", ["fit-damping", "m.csv", "-o", "r.toml", "--max-hz", "-5"],
     "--max-hz", "-5", "must be > 0 and <= 1e5 Hz"),
    ("ema-band-reversed", ["ema", "f.uff", "-o", "m.csv", "--band", "160:2"], "--band",
     "160:2", "expected LO < HI"),
    ("ema-band-one", ["ema", "f.uff", "-o", "m.csv", "--band", "160"], "--band", "160",
     "expected LO:HI"),
    ("ema-max-order", ["ema", "f.uff", "-o", "m.csv", "--max-order", "0"], "--max-order", "0",
     "outside 1..200"),
    ("ema-min-stable", ["ema", "f.uff", "-o", "m.csv", "--min-stable", "0"], "--min-stable",
     "0", "must be > 0 and <= 1"),
    ("compare-noise-zero", ["compare", "s.csv", "--noise", "0"], "--noise", "0",
     "must be > 0 and <= 1e4 um"),
    ("compare-freq-noise", ["compare", "s.csv", "--freq-noise", "200"], "--freq-noise", "200",
     "must be > 0 and <= 100 %"),
    ("diagnose-shape-noise", ["diagnose", "s.csv", "--shape-noise", "-2"], "--shape-noise",
     "-2", "must be > 0 and <= 100 %"),
    ("plan-series-zero", ["plan-test", "s.csv", "--hypotheses", "tilt:j1=3e7;base:k=2e7",
                          "--series", "0", "-o", "p"], "--series", "0", "outside 1..100"),
    ("plan-min-height", ["plan-test", "s.csv", "--hypotheses", "tilt:j1=3e7;base:k=2e7",
                         "--min-height", "nan", "-o", "p"], "--min-height", "nan", NOT_FINITE),
    ("compare-tcp-node", ["compare", "f.uff", "--tcp-node", "0"], "--tcp-node", "0",
     "outside 1"),
]:
    _option(f"number-{id_}", argv, option, value, re.escape(why))
case("number-plan-hypothesis-negative", lambda t: [
    "plan-test", "s.csv", "--hypotheses", "tilt:j1=-3e7;stiffness:j2=1", "-o", "p"],
    re.escape("--hypotheses 'tilt:j1=-3e7': tilt stiffness -3e7: must be > 0"))
