import numpy as np

from flexarm.studies.compensation.solve.runs import PathRun, circle_of, path_deviation


def test_path_deviation_is_the_distance_to_the_polyline():
    rng = np.random.default_rng(0)
    ref = np.cumsum(rng.uniform(0.0, 1.0, (60, 3)), axis=0)
    pts = ref[5:50] + rng.normal(0, 0.05, (45, 3))
    d = path_deviation(pts, ref)
    # brute force over every segment
    a, b = ref[:-1], ref[1:]
    e = b - a
    t = np.clip(np.einsum("psk,sk->ps", pts[:, None] - a[None], e) / np.sum(e * e, 1), 0, 1)
    dist = np.linalg.norm(pts[:, None] - (a[None] + t[..., None] * e[None]), axis=2).min(1)
    assert np.allclose(np.linalg.norm(d, axis=1), dist, rtol=0, atol=1e-12)


def test_radial_deviation_about_the_programmed_circle():
    phi = np.linspace(0, 2 * np.pi, 200)
    ref = np.c_[1.3 + 0.155 * np.cos(phi), 0.05 + 0.155 * np.sin(phi), np.full(200, 0.6)]
    circle = circle_of(ref)
    assert circle is not None and abs(circle[2] - 0.155) < 1e-12
    assert circle_of(np.c_[ref[:, 0], ref[:, 1], 0.6 + 1e-3 * phi]) is None
    pts = ref + np.c_[1e-4 * np.cos(phi), 1e-4 * np.sin(phi), np.full(200, 2e-5)]
    run = PathRun("c", ref, pts, path_deviation(pts, ref), circle)
    assert np.allclose(run.radial, 1e-4) and abs(run.rms() - 1e-4) < 1e-12
    assert run.rms(phi < 0) == 0.0
