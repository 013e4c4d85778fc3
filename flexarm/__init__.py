"""flexarm: finite-element substructuring and modal reduction for industrial robot arms."""

__version__ = "0.1.0"
