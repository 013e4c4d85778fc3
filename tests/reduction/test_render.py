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
def test_png_and_gif(se, tmp_path, monkeypatch):
    monkeypatch.setenv("FLEXARM_CACHE", str(tmp_path / "cache"))  # really drawn here
    png = render.render_mode(se, 2, tmp_path / "m2.png")
    gif = render.render_mode(se, 1, tmp_path / "m1.gif", n_frames=4, window_size=(200, 150))
    import imageio.v3 as iio

    img = iio.imread(png)
    assert img.shape[0] > 100 and img.std() > 1
    assert iio.imread(gif, index=None).shape[0] == 4


class _FakeRun:
    """Stands in for the probe subprocess: counts calls, succeeds from call ``ok_from``."""

    def __init__(self, ok_from=0):
        self.calls, self.ok_from = [], ok_from

    def __call__(self, cmd, env=None, **_):
        self.calls.append(env.get("VTK_DEFAULT_OPENGL_WINDOW"))
        rc = 0 if len(self.calls) > self.ok_from else 1
        return type("Done", (), {"returncode": rc})()


def test_probe_result_is_cached_per_machine(tmp_path, monkeypatch):
    monkeypatch.setenv("FLEXARM_CACHE", str(tmp_path))
    monkeypatch.delenv("VTK_DEFAULT_OPENGL_WINDOW", raising=False)
    monkeypatch.delenv("DISPLAY", raising=False)
    fake = _FakeRun(ok_from=1)  # EGL fails, OSMesa works
    monkeypatch.setattr(render.subprocess, "run", fake)
    try:
        render.render_backend.cache_clear()
        assert render.render_backend() == "vtkOSOpenGLRenderWindow" and len(fake.calls) == 2
        # a new process (its memo forgotten, the variable it set gone) reads the answer
        render.render_backend.cache_clear()
        monkeypatch.delenv("VTK_DEFAULT_OPENGL_WINDOW")
        assert render.render_backend() == "vtkOSOpenGLRenderWindow" and len(fake.calls) == 2
        assert list((tmp_path / "render-probe").glob("*.json"))
        # another display is another answer: probed again
        render.render_backend.cache_clear()
        monkeypatch.delenv("VTK_DEFAULT_OPENGL_WINDOW")
        monkeypatch.setenv("DISPLAY", ":7")
        render.render_backend()
        assert len(fake.calls) == 3
    finally:
        render.render_backend.cache_clear()


def test_failed_probe_is_not_cached(tmp_path, monkeypatch):
    monkeypatch.setenv("FLEXARM_CACHE", str(tmp_path))
    monkeypatch.delenv("VTK_DEFAULT_OPENGL_WINDOW", raising=False)
    fake = _FakeRun(ok_from=99)
    monkeypatch.setattr(render.subprocess, "run", fake)
    try:
        render.render_backend.cache_clear()
        with pytest.raises(FlexarmError, match="cannot render off-screen"):
            render.render_backend()
        fake.ok_from = 0
        render.render_backend.cache_clear()
        assert render.render_backend() == "vtkEGLRenderWindow" and len(fake.calls) == 4
    finally:
        render.render_backend.cache_clear()


@pytest.mark.render
def test_pictures_come_from_the_cache_until_the_field_changes(se, tmp_path, monkeypatch):
    monkeypatch.setenv("FLEXARM_CACHE", str(tmp_path / "cache"))
    draws = []
    real = render._draw_field
    monkeypatch.setattr(render, "_draw_field", lambda *a: (draws.append(a[2]), real(*a))[1])
    opts = {"n_frames": 3, "window_size": (160, 120)}
    first = render.render_mode(se, 1, tmp_path / "a.gif", **opts)
    again = render.render_mode(se, 1, tmp_path / "b.gif", **opts)
    assert len(draws) == 1 and first.read_bytes() == again.read_bytes()
    other = render.render_mode(se, 2, tmp_path / "c.gif", **opts)  # another field
    assert len(draws) == 2 and other.read_bytes() != first.read_bytes()
    _, u = mode_shape(se, 1, "fixed")
    nudged = u.copy()
    nudged[se.surface_nodes[0], 0] += 1e-12 * np.abs(u).max()
    render.render_field(se, nudged, tmp_path / "d.gif", title="fixed-interface mode 1: "
                        f"{se.freq_hz[0]:.2f} Hz", **opts)
    assert len(draws) == 3
    render.render_mode(se, 1, tmp_path / "e.gif", **{**opts, "n_frames": 4})
    assert len(draws) == 4


def test_picture_of_a_superelement_without_surface_says_why(se, tmp_path, monkeypatch):
    import dataclasses

    monkeypatch.setattr(render, "render_backend", lambda: "")
    bare = dataclasses.replace(se, surface_points=None, surface_nodes=None)
    with pytest.raises(FlexarmError, match="no surface mesh"):
        render.render_mode(bare, 1, tmp_path / "m.png")
    assert not (tmp_path / "m.png").exists()
