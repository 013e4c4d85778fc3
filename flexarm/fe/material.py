"""Isotropic linear-elastic materials."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Material", "MATERIALS", "material_from_string"]


@dataclass(frozen=True)
class Material:
    """Isotropic linear elastic material.

    Parameters
    ----------
    E : float
        Young's modulus [Pa], > 0.
    nu : float
        Poisson ratio [-], -1 < nu < 0.5.
    rho : float
        Density [kg/m^3], >= 0.
    name : str
        Label for reports.

    Examples
    --------
    >>> steel = MATERIALS["steel"]
    >>> round(steel.lame_mu / 1e9, 3)  # shear modulus [GPa]
    80.769
    """

    E: float
    nu: float
    rho: float
    name: str = "custom"

    def __post_init__(self) -> None:
        if not self.E > 0:
            raise ValueError(f"Young's modulus E must be > 0 Pa, got {self.E}")
        if not -1.0 < self.nu < 0.5:
            raise ValueError(f"Poisson ratio must be in (-1, 0.5), got {self.nu}")
        if not self.rho >= 0:
            raise ValueError(f"density must be >= 0 kg/m^3, got {self.rho}")

    @property
    def lame_lambda(self) -> float:
        """First Lamé parameter [Pa]."""
        return self.E * self.nu / ((1 + self.nu) * (1 - 2 * self.nu))

    @property
    def lame_mu(self) -> float:
        """Shear modulus [Pa]."""
        return self.E / (2 * (1 + self.nu))

    def scaled_stiffness(self, factor: float) -> Material:
        """Same material with E multiplied by ``factor`` (stiff-link limit checks)."""
        return Material(self.E * factor, self.nu, self.rho, f"{self.name}*{factor:g}")


MATERIALS: dict[str, Material] = {
    "steel": Material(210e9, 0.3, 7850.0, "steel"),
    # Nodular cast iron (EN-GJS-400), the usual robot-casting material.
    "cast_iron": Material(169e9, 0.275, 7100.0, "cast_iron"),
    "aluminium": Material(70e9, 0.33, 2700.0, "aluminium"),
    "nafems": Material(200e9, 0.3, 8000.0, "nafems"),
}


def material_from_string(text: str) -> Material:
    """Parse ``"steel"`` (a known name) or ``"E,nu,rho"`` in SI units.

    Examples
    --------
    >>> material_from_string("210e9,0.3,7850").rho
    7850.0
    """
    key = text.strip().lower()
    if key in MATERIALS:
        return MATERIALS[key]
    parts = key.split(",")
    if len(parts) != 3:
        names = "|".join(MATERIALS)
        raise ValueError(f"material must be one of {names} or 'E,nu,rho' in SI units, got '{text}'")
    try:
        E, nu, rho = (float(p) for p in parts)
    except ValueError:
        raise ValueError(f"material 'E,nu,rho' must be three numbers, got '{text}'") from None
    return Material(E, nu, rho)
