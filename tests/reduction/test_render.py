import numpy as np
import pytest
from reduction_helpers import STEEL

from flexarm.fe import FlexarmError
from flexarm.reduction import render
from flexarm.reduction.recovery import mode_shape
from flexarm.reduction.reduce import reduce_part


@pytest.fixture(scope="module")
def se(bar):
    mesh, regions, KM = bar
    return reduce_part(mesh, STEEL, regions, "rbe2", "cb", 4, matrices=KM)


def test_mode_shape_fixed_and_free(se):
    f, u = mode_shape(se, 1, "fixed")
    assert f == se.freq_hz[0] and np.isclose(np.abs(u).max(), 1.0)
    f_free, _ = mode_shape(se, 1, "free")
    assert f_free > 0
    with pytest.raises(ValueError, match="has 4 fixed-interface modes"):
        mode_shape(se, 5, "fixed")


def test_interactive_without_display(se, monkeypatch):
    monkeypatch.setattr(render, "has_display", lambda: False)
    with pytest.raises(FlexarmError, match="--interactive needs a display"):
        render.render_mode(se, 1, interactive=True)


def test_probe_failure_is_clear(monkeypatch):
    render.render_backend.cache_clear()
    monkeypatch.setattr(render, "_PROBE", "import sys; sys.exit(1)")
    monkeypatch.delenv("VTK_DEFAULT_OPENGL_WINDOW", raising=False)
    try:
        with pytest.raises(FlexarmError, match="cannot render off-screen"):
            render.render_backend()
    finally:
        render.render_backend.cache_clear()


@pytest.mark.render
def test_png_and_gif(se, tmp_path):
    png = render.render_mode(se, 2, tmp_path / "m2.png")
    gif = render.render_mode(se, 1, tmp_path / "m1.gif", n_frames=4, window_size=(200, 150))
    import imageio.v3 as iio

    img = iio.imread(png)
    assert img.shape[0] > 100 and img.std() > 1
    assert iio.imread(gif, index=None).shape[0] == 4
