import numpy as np

from flexarm.assembly.analyses import natural_frequencies, tcp_compliance
from flexarm.assembly.emodel import emodel
from flexarm.assembly.maps import stiffest, stiffness_map, write_csv


def test_map_matches_pointwise(demo_robot, tmp_path):
    arm = emodel(demo_robot, method="surface")
    q = demo_robot.pose("P1")
    a, b = np.linspace(-0.5, 1.0, 5), np.linspace(-1.0, 0.5, 4)
    m = stiffness_map(arm, q, a, b)
    qq = q.copy()
    qq[1], qq[2] = a[3], b[1]
    C = tcp_compliance(arm, qq)
    assert np.allclose(m.stiffness[3, 1], 1 / np.diag(C)[:3], rtol=1e-12)
    assert np.isclose(m.freq_hz[3, 1], natural_frequencies(arm, qq)[0], rtol=1e-12)
    best = stiffest(m)
    assert best["y"][2] == m.stiffness[..., 1].max()
    text = write_csv(tmp_path / "m.csv", m).read_text().splitlines()
    assert text[0].startswith("q2_deg,q3_deg,kxx_N_per_mm") and len(text) == 21
