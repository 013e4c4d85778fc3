"""Split long motions into shorter ones, so a compensated path can follow the deflection.

A shifted target moves the tool where the load pushes it *at that target*.  Between
targets the controller interpolates a line or an arc through the shifted targets, while
the deflection changes along the motion (a ball bar's push turns with the tool, the arm
is stiffer one way than the other): on the thesis's circles, four targets per turn leave
about a quarter of the deviation.  :func:`densify` writes every ``MoveL`` and ``MoveC``
longer than ``max_mm`` as equal sub-motions (``MoveC`` as sub-arcs of the same circle,
each with its own circle point) through new robtargets on the programmed path; every
other character of the module stays.  The new robtargets are declared right after the
motion's ``ToPoint``, named after it (``Target_90_1``, its circle point
``Target_90_1c``), with the configuration the arm has there; the instruction text
(speed, zone, tool, optional arguments) is copied for each sub-motion.

Joint moves (``MoveJ``) and motions to unnamed targets are left as they are.
"""

from __future__ import annotations

import math
import re
from dataclasses import replace

import numpy as np

from ....robot.formats.rapid import RapidModule
from ....robot.ik_path import rapid_conf
from .program_path import ProgramPath
from .rapid_out import POS_DECIMALS, QUAT_DECIMALS, _number, module_of_text

__all__ = ["densify"]

_MAX_NAME = 32  # RAPID identifiers


def _statement(text: str, line: int) -> tuple[int, int, str]:
    """(start, end, indentation) of the statement starting on 1-based ``line``: from its
    first character to just after its ``;``, outside comments and strings."""
    starts = [0] + [m.end() for m in re.finditer("\n", text)]
    i = starts[line - 1]
    indent = re.match(r"[ \t]*", text[i:]).group(0)
    j, in_str = i + len(indent), False
    while j < len(text):
        c = text[j]
        if c == '"':
            in_str = not in_str
        elif c == "!" and not in_str:
            j = text.find("\n", j)
            continue
        elif c == ";" and not in_str:
            return i + len(indent), j + 1, indent
        j += 1
    raise ValueError(f"line {line}: no ';' ends the instruction")


def _declaration_end(text: str, name: str) -> tuple[int, str]:
    """(index after the line declaring robtarget ``name``, that line's text before
    ``robtarget``, e.g. ``"    CONST "``)."""
    m = re.search(r"^([ \t]*(?:LOCAL\s+)?(?:CONST|PERS|VAR)\s+)robtarget\s+" + re.escape(name)
                  + r"\s*:=", text, re.IGNORECASE | re.MULTILINE)
    if m is None:
        raise ValueError(f"robtarget '{name}' has no declaration line to add targets after")
    end = text.find(";", m.end())
    nl = text.find("\n", end)
    return (len(text) if nl < 0 else nl + 1), m.group(1)


def _fresh(base: str, used: set[str]) -> str:
    """A RAPID name like ``base`` (at most 32 characters) not in ``used`` (lower case)."""
    name, k = base[:_MAX_NAME], 2
    while name.lower() in used:
        tail = f"_{k}"
        name, k = base[:_MAX_NAME - len(tail)] + tail, k + 1
    used.add(name.lower())
    return name


def _literal(pos, quat, conf, extax) -> str:
    p = ",".join(_number(x, POS_DECIMALS) for x in pos)
    q = ",".join(_number(x, QUAT_DECIMALS) for x in quat)
    c = ",".join(str(int(x)) for x in conf)
    e = ",".join("9E+09" if x >= 9e9 * (1 - 1e-6) else _number(x, POS_DECIMALS) for x in extax)
    return f"[[{p}],[{q}],[{c}],[{e}]]"


def _sub_samples(pp: ProgramPath, k: int, n_sub: int, is_arc: bool) -> list[tuple]:
    """Sample indices of the ``n_sub`` sub-motions of motion ``k``: (circle point or None,
    end), the last end being the motion's own."""
    rows = np.flatnonzero(pp.path.segments == k)
    arc = pp.path.arc_length_mm[rows]
    a0 = float(pp.path.arc_length_mm[rows[0] - 1]) if rows[0] > 0 else float(arc[0])
    length = float(arc[-1]) - a0
    out = []
    for i in range(1, n_sub + 1):
        end = int(rows[-1]) if i == n_sub else int(rows[np.argmin(np.abs(arc - a0 - length * i
                                                                             / n_sub))])
        cir = None
        if is_arc:
            cir = int(rows[np.argmin(np.abs(arc - a0 - length * (i - 0.5) / n_sub))])
        out.append((cir, end))
    return out


def densify(text: str, module: RapidModule, pps: tuple[ProgramPath, ...], chain,
            max_mm: float) -> tuple[str, list[str]]:
    """``text`` with every ``MoveL``/``MoveC`` of the program paths ``pps`` longer than
    ``max_mm`` [mm] split into equal sub-motions through new robtargets.

    Parameters
    ----------
    text : str
        The module's source.
    module : RapidModule
        The same, read.
    pps : tuple of ProgramPath
        Its procedures as the arm runs them (:func:`~.program_path.program_paths`), sampled
        finely enough to place the new targets (a step of ``max_mm / 4`` or less).
    chain : Chain
        The robot's kinematics (for the new targets' configuration).
    max_mm : float
        Longest motion kept [mm].

    Returns
    -------
    text : str
    notes : list of str
        One line per split motion.

    Examples
    --------
    >>> from flexarm.robot.demo_arm import load_demo_robot
    >>> from flexarm.robot.formats.rapid import read_rapid
    >>> from flexarm.studies.contact.loaded_circle import THESIS_RAPID
    >>> from flexarm.studies.compensation.program import program_paths
    >>> r, mod = load_demo_robot(), read_rapid(THESIS_RAPID)
    >>> pps = program_paths(r, mod, ["Path_30"], step_mm=5)
    >>> new, notes = densify(THESIS_RAPID.read_text(), mod, pps, r.chain, 150.0)
    >>> notes[0]
    'Path_30: MoveC via Target_80 to Target_90 (line 71) split in 4 (121.7 mm each)'
    >>> "MoveC Target_90_1c,Target_90_1,v10,fine,tool0\\\\WObj:=wobj0;" in new
    True
    """
    if not max_mm > 0:
        raise ValueError(f"split length must be > 0 mm, got {max_mm}")
    used = {n.lower() for n in (*module.targets, *module.joint_targets, *module.data,
                                *module.procedures)}
    made: dict[tuple, list[tuple[str | None, str]]] = {}
    decls: dict[str, list[str]] = {}
    edits, notes = [], []
    # the motions' lines in ``text`` itself: a module read from a CSV or KRL program
    # carries the line numbers of that file, not of the generated RAPID text
    at_line = {p.lower(): [m.line for m in pr.motions]
               for p, pr in module_of_text(text).procedures.items()}
    for pp in pps:
        proc = module.procedure(pp.name)
        ch = replace(chain, tool=pp.tool)
        starts = [None] + [m.to_point.name for m in proc.motions[:-1]]
        for k, m in enumerate(proc.motions):
            rows = np.flatnonzero(pp.path.segments == k)
            if m.kind not in ("MoveL", "MoveC") or k == 0 and rows[0] == 0 and len(rows) == 1:
                continue
            named = all(t.name.lower() in {n.lower() for n in module.targets}
                        for t in m.targets)
            a = pp.path.arc_length_mm
            length = float(a[rows[-1]] - (a[rows[0] - 1] if rows[0] > 0 else a[rows[0]]))
            n_sub = math.ceil(length / max_mm - 1e-9)
            if not named or n_sub < 2:
                continue
            key = (m.kind, starts[k], *(t.name.lower() for t in m.targets), n_sub)
            to = m.to_point
            if key not in made:
                subs = []
                for i, (cir, end) in enumerate(_sub_samples(pp, k, n_sub, m.kind == "MoveC")):
                    names = []
                    for s, suffix in ((cir, "c"), (end, "")):
                        if s is None:
                            names.append(None)
                            continue
                        if i == n_sub - 1 and suffix == "":
                            names.append(to.name)
                            continue
                        nm = _fresh(f"{to.name}_{i + 1}{suffix}", used)
                        lit = _literal(pp.path.points_mm[s], pp.path.quats[s],
                                       rapid_conf(ch, pp.q[s]), to.extax)
                        decls.setdefault(to.name, []).append(f"{nm}:={lit};")
                        names.append(nm)
                    subs.append(tuple(names))
                made[key] = subs
            a0, b0, indent = _statement(text, at_line[pp.name.lower()][k])
            body = text[a0:b0]
            lines = []
            for cir, end in made[key]:
                sub = body
                if cir is not None:
                    sub = re.sub(rf"\b{re.escape(m.cir_point.name)}\b", cir, sub, count=1)
                sub = re.sub(rf"\b{re.escape(to.name)}\b", end, sub, count=1) if end != to.name \
                    else sub
                lines.append(sub)
            edits.append((a0, b0, ("\n" + indent).join(lines)))
            notes.append(f"{pp.name}: {pp.path.motion_text(k)} split in {n_sub} "
                         f"({length / n_sub:.1f} mm each)")
    for name, items in decls.items():
        at, prefix = _declaration_end(text, name)
        edits.append((at, at, "".join(f"{prefix}robtarget {d}\n" for d in items)))
    for a, b, s in sorted(edits, key=lambda e: e[0], reverse=True):
        text = text[:a] + s + text[b:]
    return text, notes
