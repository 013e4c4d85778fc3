"""One demo run, read back: every matplotlib picture as a figure object (a title naming
the model and the pose(s), labelled axes with units, a legend wherever more than one
series is drawn), and every figure the README quotes from the demo, recomputed from the
files the run wrote.  Two fresh runs in empty caches write the same tables (slow)."""

from __future__ import annotations

import csv
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from .demo_golden import GOLDEN, differences, fingerprint

README = Path(__file__).resolve().parents[2] / "README.md"

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
    """``{path in the demo folder: Figure}`` of one in-process demo run, and
    ``{path: title}`` of its 3-D renders of the arm (``RENDERS``)."""
    import matplotlib.figure

    from flexarm.fe import plotting
    from flexarm.studies import render_arm
    from flexarm.studies.demo import run_demo

    saved = {}
    real = matplotlib.figure.Figure.savefig

    def savefig(self, fname, *args, **kwargs):
        saved[str(fname)] = self
        return real(self, fname, *args, **kwargs)

    real_render = render_arm.render_arm

    def render(fields, path=None, title="", *args, **kwargs):
        RENDERS[str(path)] = title
        return real_render(fields, path, title, *args, **kwargs)

    def draw(path, key, draw, serve=None):  # plots keyed by their inputs: build the figure
        draw(Path(path))
        return Path(path), False

    out = tmp_path_factory.mktemp("demo") / "flexarm-demo"
    mp = pytest.MonkeyPatch()
    mp.setattr(matplotlib.figure.Figure, "savefig", savefig)
    mp.setattr(plotting, "cached_picture", draw)
    mp.setattr(render_arm, "render_arm", render)
    try:
        run_demo(out, jobs=1)  # one process: every figure passes through this savefig
    finally:
        mp.undo()
    renders = {_relative(f, out.name): t for f, t in RENDERS.items()}
    RENDERS.clear()
    RENDERS.update(renders)
    return out, {_relative(f, out.name): fig for f, fig in saved.items()}


#: Titles of the demo's 3-D renders, by path in the demo folder (filled by demo_figures).
RENDERS: dict = {}


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
    # the 3-D renders (PNG and GIF) name model and pose in their titles too
    renders = {str(p.relative_to(out)) for p in out.rglob("*") if p.suffix in (".png", ".gif")}
    assert set(RENDERS) >= renders - drawn and len(RENDERS) >= 2, (set(RENDERS), renders)
    for name, title in RENDERS.items():
        assert MODELS.search(title) and POSES.search(title), (name, title)


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


def _csv(path: Path) -> list[dict]:
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def _readme_demo_section(page: Path = README) -> str:
    text = page.read_text()
    start = text.index("## What the demo shows")
    end = text.find("\n## ", start + 1)
    return " ".join(text[start:end if end > 0 else None].split())


def _expected(out: Path) -> list[str]:
    """The README's demo figures, formatted from the run's own files."""
    index = (out / "index.md").read_text()
    said = []
    for r in _csv(out / "emodel_poses.csv"):
        d = [float(r[f"d{c}_800N_mm"]) for c in "xyz"]
        said.append(f"| {r['pose']} | {float(r['f1_Hz']):.2f} | "
                    + " / ".join(f"{v:.2f}" for v in d) + f" | {r['weakest'].upper()} |")
    flexible = index[index.index("## The flexible arm"):]
    said += [line for line in flexible.splitlines() if re.match(r"\| P\d \|", line)]
    said.append(re.search(r"IRB 4600-class arm, (\d+\.\d) kg", index).group(1) + " kg")
    shares = re.findall(r"least stiff direction on (\d+\.\d)% of the grid", index)
    said.append(f"{shares[0]} % (E-model) and {shares[1]} % (flexible)")
    study = _csv(out / "study" / "arm_study.csv")
    ref, cb, guyan = (next(r for r in study if r["label"] == name and r["coupling"] == "rbe2")
                      for name in ("full-FE", "CB(10)", "Guyan"))
    # static condensation is exact at the interfaces: the compliance error is round-off of
    # the 46k-DOF reference's factorisation, which differs between BLAS builds and thread
    # counts (1.2e-12 seen with one thread), so the README gives a bound with room
    assert float(cb["C_err_max"]) < 1e-10
    said.append(f"reference at P1 ({int(ref['n_fe_dofs']):,} DOF), CB(10) with "
                f"{cb['n_reduced']} arm coordinates is within "
                f"{100 * float(cb['freq_err_max']):.3g} % on the first 10 frequencies and "
                "below 1e-10 (round-off) on the TCP compliance")
    said.append(f"Guyan ({guyan['n_reduced']} coordinates) is within "
                f"{100 * float(guyan['freq_err_max']):.2g} %")
    mesh = _csv(out / "study" / "arm_study_mesh_error.csv")
    change = [100 * float(r["rel_change"]) for r in mesh]
    worst = max(range(len(change)), key=change.__getitem__)
    said.append(f"{change[0]:.2g} % lower on f1 and up to {change[worst]:.2g} % lower "
                f"(mode {worst + 1})")
    models = _csv(out / "models" / "model_comparison.csv")
    moves, first3, c_move = [], 0.0, (0.0, "")
    for pose in ("P1", "P2", "P3"):
        cb10, wrist = (next(r for r in models if r["pose"] == pose and r["model"] == m)
                       for m in ("CB(10)", "CB(10)+wrist"))
        df = [abs(float(wrist[f"f{i}_Hz"]) / float(cb10[f"f{i}_Hz"]) - 1) for i in range(1, 11)]
        moves.append(f"{100 * max(df):.2g}")
        first3 = max(first3, *df[:3])
        for c in ("xx", "yy", "zz"):
            dc = abs(float(wrist[f"C{c}_mm_per_kN"]) / float(cb10[f"C{c}_mm_per_kN"]) - 1)
            c_move = max(c_move, (dc, f"{pose} C{c}"))
    said.append(f"by up to {' / '.join(moves)} % at P1 / P2 / P3 and the TCP compliance by up "
                f"to {100 * c_move[0]:.2f} % ({c_move[1]})")
    assert first3 < 1e-5
    said.append(re.search(r"joint 2 backlash of (\S+ ± \S+ mrad)", index).group(1))
    nominal = re.search(r"Nominal model: χ²_red (\S+),", index).group(1)
    final = re.search(r"χ²_red (\S+) \(band (\S+)\)", index)
    said.append(f"falls from {nominal} (nominal file) to {final.group(1)} (band "
                f"{final.group(2)})")
    return said


@pytest.mark.parametrize("page", [README, README.parent / "docs" / "getting_started.md"],
                         ids=["readme", "getting_started"])
def test_readme_quotes_the_demo_to_the_printed_digits(demo_figures, page):
    out, _ = demo_figures
    section = _readme_demo_section(page)
    missing = [s for s in _expected(out) if " ".join(s.split()) not in section]
    assert not missing, f"{page.name} differs from the demo run:\n" + "\n".join(missing)


#: Columns that hold wall times: the only cells two runs may differ in.
_TIMES = re.compile(r"seconds|time_s$")


def _tables(folder: Path) -> dict[str, list[list[str]]]:
    """Every CSV of a demo folder, time columns blanked."""
    tables = {}
    for path in sorted(folder.rglob("*.csv")):
        with open(path, newline="") as fh:
            rows = list(csv.reader(fh))
        keep = [i for i, name in enumerate(rows[0]) if not _TIMES.search(name)] if rows else []
        tables[str(path.relative_to(folder))] = [[r[i] for i in keep if i < len(r)]
                                                 for r in rows]
    return tables


@pytest.mark.slow
def test_two_fresh_demos_write_identical_tables(tmp_path):
    import os

    runs = []
    for name in ("a", "b"):
        env = dict(os.environ, FLEXARM_CACHE=str(tmp_path / name / "cache"))
        subprocess.run([sys.executable, "-m", "flexarm.cli", "-q", "demo", "-o",
                        str(tmp_path / name / "out")], env=env, check=True)
        runs.append(_tables(tmp_path / name / "out"))
    a, b = runs
    assert a.keys() == b.keys() and len(a) >= 15
    for name in a:
        assert a[name] == b[name], name


def test_every_table_matches_the_golden_run(demo_figures):
    """The demo's CSVs hold the numbers of the committed golden run (rtol 1e-7 of each
    column's largest number; wall-clock columns left out), so a move of code that should
    change nothing changes nothing."""
    out, _ = demo_figures
    golden = json.loads(GOLDEN.read_text())
    assert differences(fingerprint(out), golden) == []
    broken = dict(golden)
    table = "emodel_poses.csv"
    broken[table] = {**golden[table], "columns": dict(golden[table]["columns"])}
    f1 = list(broken[table]["columns"]["f1_Hz"])
    f1[0] *= 1 + 1e-6
    broken[table]["columns"]["f1_Hz"] = f1
    assert len(differences(fingerprint(out), broken)) == 1
