"""Every matplotlib picture the demo writes, read back as a figure object: a title naming
the model and the pose(s), labelled axes with units, and a legend wherever more than
one series is drawn."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

#: Words that name a model in a title.
MODELS = re.compile(r"E-model|Guyan|CB|full FE|flexible|measured")
#: A pose: a thesis pose name, or a list of them.
POSES = re.compile(r"\bP\d\b")
#: A unit in an axis label: ``[mm]``, ``[-]``, or a count (DOF, modes).
UNIT = re.compile(r"\[[^\]]+\]|\bDOF\b|\bmodes\b")
_TMP_FILE = re.compile(r"^\.(.+)\.[^.]+\.part(\.\w+)$")
_TMP_FOLDER = re.compile(r"^\.(.+)\.part-\d+-\w+$")


def _relative(fname: str, root: str) -> str:
    """The picture's path in the demo folder (temporary names of atomic writes undone)."""
    parts = []
    for part in Path(fname).parts:
        m = _TMP_FILE.match(part) or _TMP_FOLDER.match(part)
        parts.append("".join(m.groups()) if m else part)
    return "/".join(parts[parts.index(root) + 1:])


@pytest.fixture(scope="module")
def demo_figures(tmp_path_factory):
    """``{path in the demo folder: Figure}`` of one in-process demo run."""
    import matplotlib.figure

    from flexarm.studies.demo import run_demo

    saved = {}
    real = matplotlib.figure.Figure.savefig

    def savefig(self, fname, *args, **kwargs):
        saved[str(fname)] = self
        return real(self, fname, *args, **kwargs)

    out = tmp_path_factory.mktemp("demo") / "flexarm-demo"
    mp = pytest.MonkeyPatch()
    mp.setattr(matplotlib.figure.Figure, "savefig", savefig)
    try:
        run_demo(out, jobs=1)  # one process: every figure passes through this savefig
    finally:
        mp.undo()
    return out, {_relative(f, out.name): fig for f, fig in saved.items()}


def _data_axes(fig):
    return [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]


def _titles(fig) -> str:
    sup = fig._suptitle.get_text() if fig._suptitle is not None else ""
    return " | ".join([sup, *(ax.get_title() for ax in fig.axes)])


def _label(fig, ax, axis: str) -> str:
    """The axis label of ``ax``, else of an axes sharing that axis, else the figure's."""
    own = getattr(ax, f"get_{axis}label")()
    if own:
        return own
    shared = getattr(ax, f"get_shared_{axis}_axes")()
    for other in fig.axes:
        if other is not ax and shared.joined(ax, other) and getattr(other, f"get_{axis}label")():
            return getattr(other, f"get_{axis}label")()
    sup = getattr(fig, f"_sup{axis}label", None)
    return sup.get_text() if sup is not None else ""


def _categorical(ax, axis: str) -> bool:
    """Ticks named by words (poses, versions): no unit to give."""
    def number(text: str) -> bool:
        try:
            float(text.replace("\N{MINUS SIGN}", "-").replace("$", ""))
        except ValueError:
            return False
        return True

    texts = [t.get_text() for t in getattr(ax, f"get_{axis}ticklabels")() if t.get_text()]
    return bool(texts) and not any(number(t) for t in texts)


def _n_series(ax) -> int:
    """Lines of more than two points (not a box plot's closed boxes or its parts), scatter
    sets and bar groups."""
    lines = [ln for ln in ax.get_lines() if len(ln.get_xdata()) > 2
             and ln.get_label() != "_nolegend_"
             and not (ln.get_xydata()[0] == ln.get_xydata()[-1]).all()]
    scatters = [c for c in ax.collections if len(c.get_offsets()) > 2
                and type(c).__name__ == "PathCollection"]
    return len(lines) + len(scatters) + len(ax.containers)


def _problems(name: str, fig) -> list[str]:
    out = []
    titles = _titles(fig)
    if not MODELS.search(titles):
        out.append(f"{name}: no model named in the title ({titles!r})")
    if not POSES.search(titles):
        out.append(f"{name}: no pose named in the title ({titles!r})")
    for i, ax in enumerate(_data_axes(fig)):
        for axis in "xy":
            label = _label(fig, ax, axis)
            if not label:
                out.append(f"{name}: axes {i} has no {axis} label")
            elif not _categorical(ax, axis) and not UNIT.search(label):
                out.append(f"{name}: axes {i} {axis} label {label!r} has no unit")
    has_legend = bool(fig.legends) or any(ax.get_legend() is not None for ax in fig.axes)
    if any(_n_series(ax) > 1 for ax in _data_axes(fig)) and not has_legend:
        out.append(f"{name}: several series and no legend")
    return out


def test_every_demo_picture_names_model_pose_units_and_series(demo_figures):
    out, figures = demo_figures
    pngs = {str(p.relative_to(out)) for p in out.rglob("*.png")}
    drawn = set(figures)
    # every matplotlib PNG in the folder was seen; the others are the 3-D renders
    assert drawn <= pngs and pngs - drawn <= {"arm_P1_mode2.png"}, pngs ^ drawn
    assert len(drawn) >= 18
    problems = [p for name, fig in sorted(figures.items()) for p in _problems(name, fig)]
    assert not problems, "\n".join(problems)


def test_checker_catches_a_bare_picture(figures, tmp_path):
    from flexarm.fe.plotting import pyplot, save_figure

    fig, ax = pyplot().subplots()
    ax.plot([1, 2, 3], [1, 4, 9])
    ax.plot([1, 2, 3], [2, 3, 4])
    ax.set_xlabel("load")
    save_figure(fig, tmp_path / "bare.png")
    assert _problems("bare.png", figures["bare.png"]) == [
        "bare.png: no model named in the title (' | ')",
        "bare.png: no pose named in the title (' | ')",
        "bare.png: axes 0 x label 'load' has no unit",
        "bare.png: axes 0 has no y label",
        "bare.png: several series and no legend",
    ]
