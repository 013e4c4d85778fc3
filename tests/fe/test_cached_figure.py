"""matplotlib figures served from the picture cache: same content -> same bytes without a
draw (even from another process), any change of what is drawn -> a redraw."""

import subprocess
import sys

import numpy as np
import pytest

from flexarm.fe.plotting import pyplot, save_figure

pytest.importorskip("matplotlib")

#: Draws one figure from argv's numbers into argv[1] in a fresh process and prints
#: whether it came from the cache (so nothing from this process's state can leak in).
_CHILD = """
import sys, numpy as np
import flexarm.fe.cached_figure as cf
from flexarm.fe.plotting import pyplot
drawn = []
orig = cf.CachedFigure._draw
cf.CachedFigure._draw = lambda self, *a, **k: (drawn.append(1), orig(self, *a, **k))[1]
plt = pyplot()
fig, ax = plt.subplots(1, 2, figsize=(5, 3), sharey=True)
y = np.array([float(v) for v in sys.argv[2:]])
ax[0].plot(y, label="y"); ax[0].legend(); ax[1].bar(np.arange(len(y)), y)
fig.colorbar(ax[1].imshow(np.outer(y, y)), ax=ax[1])
fig.tight_layout()
fig.savefig(sys.argv[1], dpi=60)
plt.close(fig)
print("DRAWN" if drawn else "CACHED")
"""


@pytest.fixture
def cache(tmp_path, monkeypatch):
    folder = tmp_path / "cache"
    monkeypatch.setenv("FLEXARM_CACHE", str(folder))
    return folder


def _child(path, values, cache) -> str:
    env = {"FLEXARM_CACHE": str(cache), "PATH": "/usr/bin:/bin"}
    done = subprocess.run([sys.executable, "-c", _CHILD, str(path), *map(str, values)],
                          env=env, capture_output=True, text=True, check=True)
    return done.stdout.split()[-1]


def test_same_figure_in_a_new_process_is_copied_and_a_changed_one_redrawn(tmp_path, cache):
    y = [1.0, 3.0, 2.0, 5.0]
    assert _child(tmp_path / "a.png", y, cache) == "DRAWN"
    assert _child(tmp_path / "b.png", y, cache) == "CACHED"
    assert (tmp_path / "a.png").read_bytes() == (tmp_path / "b.png").read_bytes()
    # one value changed in the last digit that a float repr keeps: drawn again
    assert _child(tmp_path / "c.png", [1.0, 3.0, 2.0, 5.000000000001], cache) == "DRAWN"
    assert _child(tmp_path / "d.png", [1.0, 3.0, 2.0, 5.000000000001], cache) == "CACHED"
    assert (tmp_path / "c.png").read_bytes() == (tmp_path / "d.png").read_bytes()


def _figure(y, title="t"):
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(4, 3))
    ax.plot(y)
    ax.set_title(title)
    return fig


def test_cached_bytes_equal_a_plain_matplotlib_draw(tmp_path, cache):
    """The deferred tight_layout draws exactly what matplotlib's own eager one draws."""
    import matplotlib.pyplot as plt

    y = np.sin(np.linspace(0, 3, 50))
    save_figure(_figure(y), tmp_path / "cached.png", dpi=70)
    save_figure(_figure(y), tmp_path / "hit.png", dpi=70)
    fig, ax = plt.subplots(figsize=(4, 3))
    ax.plot(y)
    ax.set_title("t")
    fig.tight_layout()
    fig.savefig(tmp_path / "plain.png", dpi=70)
    plt.close(fig)
    plain = (tmp_path / "plain.png").read_bytes()
    assert (tmp_path / "cached.png").read_bytes() == plain
    assert (tmp_path / "hit.png").read_bytes() == plain


def test_every_change_of_content_or_options_is_a_new_picture(tmp_path, cache):
    y = np.arange(5.0)
    save_figure(_figure(y), tmp_path / "base.png", dpi=50)
    variants = {"data": (_figure(y + 1e-9), 50), "title": (_figure(y, "u"), 50),
                "dpi": (_figure(y), 51)}
    base = (tmp_path / "base.png").read_bytes()
    for name, (fig, dpi) in variants.items():
        save_figure(fig, tmp_path / f"{name}.png", dpi=dpi)
    entries = list((cache / "pictures").glob("*.bin"))
    assert len(entries) == 1 + len(variants)
    assert (tmp_path / "title.png").read_bytes() != base
    assert (tmp_path / "dpi.png").read_bytes() != base


def test_figures_that_do_not_pickle_and_other_formats_are_drawn(tmp_path, cache):
    from matplotlib.ticker import FuncFormatter

    fig = _figure(np.arange(3.0))
    fig.axes[0].xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"<{v:g}>"))
    save_figure(fig, tmp_path / "lambda.png")
    save_figure(_figure(np.arange(3.0)), tmp_path / "vector.svg")
    assert (tmp_path / "lambda.png").stat().st_size > 0
    assert (tmp_path / "vector.svg").read_text().lstrip().startswith("<?xml")
    assert not list((cache / "pictures").glob("*.bin"))
