"""Isotropic materials: Lame parameters against E, nu (lambda, mu, bulk modulus E / 3(1 - 2 nu)),
the shipped table, scaled stiffness and the string parser."""

from __future__ import annotations

import dataclasses

import pytest

from flexarm.fe import MATERIALS, Material, material_from_string


@pytest.mark.parametrize("name", sorted(MATERIALS))
def test_lame_parameters(name):
    m = MATERIALS[name]
    assert m.lame_mu == pytest.approx(m.E / (2 * (1 + m.nu)), rel=1e-15)
    assert m.lame_lambda == pytest.approx(m.E * m.nu / ((1 + m.nu) * (1 - 2 * m.nu)), rel=1e-15)
    # bulk modulus and Young's modulus back from the Lame pair
    lam, mu = m.lame_lambda, m.lame_mu
    assert lam + 2 * mu / 3 == pytest.approx(m.E / (3 * (1 - 2 * m.nu)), rel=1e-13)
    assert mu * (3 * lam + 2 * mu) / (lam + mu) == pytest.approx(m.E, rel=1e-13)
    assert m.name == name


def test_shipped_values():
    table = {name: (m.E, m.nu, m.rho) for name, m in MATERIALS.items()}
    assert table == {"steel": (210e9, 0.3, 7850.0), "cast_iron": (169e9, 0.275, 7100.0),
                     "aluminium": (70e9, 0.33, 2700.0), "nafems": (200e9, 0.3, 8000.0)}
    assert MATERIALS["steel"].lame_mu == pytest.approx(80.769e9, rel=1e-5)


def test_scaled_stiffness_changes_only_E():
    steel = MATERIALS["steel"]
    stiff = steel.scaled_stiffness(1e6)
    assert (stiff.E, stiff.nu, stiff.rho) == (210e15, 0.3, 7850.0)
    assert stiff.name == "steel*1e+06"
    assert stiff.lame_mu == pytest.approx(1e6 * steel.lame_mu, rel=1e-15)
    assert steel.E == 210e9  # the original is untouched
    with pytest.raises(ValueError, match="Young's modulus"):
        steel.scaled_stiffness(0.0)


def test_materials_are_frozen():
    with pytest.raises(dataclasses.FrozenInstanceError):
        MATERIALS["steel"].E = 1.0


def test_material_from_string_names_and_numbers():
    assert material_from_string("  Cast_Iron ") is MATERIALS["cast_iron"]
    m = material_from_string(" 7.2e10 , 0.34, 2810 ")
    assert (m.E, m.nu, m.rho, m.name) == (7.2e10, 0.34, 2810.0, "custom")
    assert Material(1.0, 0.0, 0.0).lame_lambda == 0.0  # nu = 0: no lateral coupling


def test_material_from_string_wrong_count_lists_the_names():
    msg = ("material must be one of steel|cast_iron|aluminium|nafems or 'E,nu,rho' in SI "
           "units, got 'titanium'")
    with pytest.raises(ValueError, match="^" + msg.replace("|", r"\|") + "$"):
        material_from_string("titanium")
