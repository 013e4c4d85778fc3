"""``frf.csv``: the driving-point and cross receptances of the plotted report, and the
cross terms reciprocal (H_ij = H_ji) as a symmetric model must give."""

import numpy as np

from flexarm.assembly import emodel
from flexarm.robot import load_robot
from flexarm.studies.frf import frf_report


def test_csv_holds_the_whole_translational_receptance(tmp_path):
    robot = load_robot()
    rep = frf_report(emodel(robot), robot.pose("P1"), fmax=60.0, n=80)
    csv = rep.write(tmp_path)[1]
    head = csv.read_text().splitlines()[0].split(",")
    data = dict(zip(head, np.loadtxt(csv, delimiter=",", skiprows=1).T, strict=True))
    assert head[:3] == ["freq_Hz", "re_Hxx_m_per_N", "im_Hxx_m_per_N"] and len(head) == 19
    np.testing.assert_allclose(data["freq_Hz"], rep.freq_hz, rtol=1e-9)
    xyz = "xyz"
    H = np.stack([np.stack([data[f"re_H{a}{b}_m_per_N"] + 1j * data[f"im_H{a}{b}_m_per_N"]
                            for b in xyz], axis=-1) for a in xyz], axis=-2)
    scale = np.abs(rep.H[:, :3, :3]).max(axis=(1, 2))[:, None, None]
    assert np.all(np.abs(H - rep.H[:, :3, :3]) <= 1e-9 * scale)
    assert np.all(np.abs(H - np.swapaxes(H, 1, 2)) <= 1e-9 * scale)
    assert np.abs(H[:, 0, 1]).max() > 1e-3 * scale.max()  # the cross terms are not empty
