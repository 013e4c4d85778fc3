"""
Modes of one part
=================

A steel bar meshed with Tet10 elements, clamped at one end: its first bending
frequencies against Euler-Bernoulli, and the first mode drawn off-screen with PyVista
(``flexarm modal``).
"""

import tempfile

import matplotlib.pyplot as plt
import numpy as np

from flexarm.fe import MATERIALS, TetMesh
from flexarm.studies.part_modes import part_modes

bar = TetMesh.box((1.0, 0.05, 0.05), (40, 2, 2), order=2)
clamped = part_modes(bar, MATERIALS["steel"], 6, fix="x=min")
print(clamped.text())

# %%
# Euler-Bernoulli for a clamped-free beam: f_n = (beta_n L)^2 / (2 pi L^2) sqrt(E I / (rho A))
steel = MATERIALS["steel"]
E, rho, a = steel.E, steel.rho, 0.05
beta = np.array([1.8751, 4.6941, 7.8548])
f_eb = beta**2 / (2 * np.pi) * np.sqrt(E * a**4 / 12 / (rho * a * a))
fe = clamped.freq_hz[[0, 2, 4]]
fig, ax = plt.subplots(figsize=(6, 3.5))
ax.plot([1, 2, 3], f_eb, "o-", label="Euler-Bernoulli")
ax.plot([1, 2, 3], fe, "s--", label="Tet10 FE (flexarm)")
ax.set_xlabel("bending mode [-]")
ax.set_ylabel("frequency [Hz]")
ax.set_title("Clamped steel bar 1000 x 50 x 50 mm: bending modes")
ax.legend()
fig.tight_layout()
