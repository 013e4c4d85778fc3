"""The superelement: reduced matrices plus everything needed to use and show them.

DOF order (DESIGN §3): the boundary nodes in interface order, 6 DOFs each
(u_x, u_y, u_z, theta_x, theta_y, theta_z) for RBE2/RBE3 couplings (3 for kept region
nodes), then the Craig-Bampton modal coordinates.  Everything is SI, link frame.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from ..fe.errors import ReadError
from ..fe.mass_properties import MassProperties
from ..fe.notebook import figure, names
from ..fe.typing import FloatArray, IntArray
from .couplings import rigid_transport
from .matrix_checks import check_matrices

__all__ = [
    "FORMAT_VERSION",
    "Superelement",
    "reduced_rigid_modes",
    "matrix_mass_properties",
    "to_arrays",
    "from_arrays",
    "use_reader",
]

#: Version of the superelement data layout (all formats).
FORMAT_VERSION = 1

_OPTIONAL = ("T", "surface_points", "surface_faces", "surface_nodes")

#: The reader behind :meth:`Superelement.load`.  The format modules import this one, so
#: it cannot import them: :mod:`flexarm.reduction.formats`, which the package imports
#: before anything else, installs its ``read`` here with :func:`use_reader`.
_READER: dict = {}


def use_reader(read) -> None:
    """Make ``read(path, file_format=None) -> Superelement`` the reader of
    :meth:`Superelement.load` (called once, by :mod:`flexarm.reduction.formats`)."""
    _READER["read"] = read


@dataclass(frozen=True, eq=False)
class Superelement:
    """A reduced link (frozen).

    Attributes
    ----------
    K, M : (n, n) float
        Reduced stiffness and mass, symmetric [N/m, N, N m/rad; kg, kg m, kg m^2].
    interface_names : tuple of str
    interface_positions : (n_if, 3) float
        Interface reference points [m] (cylinder centres), link frame.
    interface_frames : (n_if, 3, 3) float
        Interface frames, columns = axes in link coordinates (z = bearing axis).
    coupling : {"rbe2", "rbe3", "nodes"}
    method : {"guyan", "cb"}
    node_positions : (n_b, 3) float
        Boundary nodes [m]; equals ``interface_positions`` for RBE2/RBE3.
    node_interface : (n_b,) int
        Interface index of each boundary node.
    dofs_per_node : {6, 3}
    freq_hz : (n_modes,) float
        Fixed-interface frequencies [Hz].
    mass : float
        [kg], from the reduced mass matrix.
    center_of_mass : (3,) float
        [m], link frame.
    inertia : (3, 3) float
        About the centre of mass [kg m^2].
    input_hash : str
        SHA-256 of mesh, material, regions and options.
    T : (3 n_nodes, n) float32 or float64, optional
        Recovery matrix: full FE displacements from reduced coordinates.
    surface_points : (p, 3) float, optional
        Surface vertices [m] for pictures.
    surface_faces : (f, 3) int, optional
        Triangles into ``surface_points``.
    surface_nodes : (p,) int, optional
        FE node of each surface vertex (rows of ``expand``).
    units : str
        Always "SI".
    version : int
        :data:`FORMAT_VERSION` of the layout.
    """

    K: FloatArray
    M: FloatArray
    interface_names: tuple
    interface_positions: FloatArray
    interface_frames: FloatArray
    coupling: str
    method: str
    node_positions: FloatArray
    node_interface: IntArray
    dofs_per_node: int
    freq_hz: FloatArray
    mass: float
    center_of_mass: FloatArray
    inertia: FloatArray
    input_hash: str
    T: np.ndarray | None = None
    surface_points: FloatArray | None = None
    surface_faces: IntArray | None = None
    surface_nodes: IntArray | None = None
    units: str = "SI"
    version: int = FORMAT_VERSION

    def __post_init__(self) -> None:
        n = np.shape(self.K)[0] if np.ndim(self.K) == 2 else -1
        if np.shape(self.K) != (n, n) or np.shape(self.M) != (n, n):
            raise ValueError(f"K and M must be square and equal, got {np.shape(self.K)} and "
                             f"{np.shape(self.M)}")
        if self.n_boundary + len(self.freq_hz) != n:
            raise ValueError(f"{len(self.node_positions)} boundary nodes x {self.dofs_per_node} "
                             f"DOFs + {len(self.freq_hz)} modes != {n} DOFs")
        object.__setattr__(self, "interface_names", tuple(str(s) for s in self.interface_names))
        for f in fields(self):
            v = getattr(self, f.name)
            if isinstance(v, np.ndarray):
                v.setflags(write=False)

    def __repr__(self) -> str:
        """One line: method, coupling, DOF split per interface, first fixed-interface
        frequencies [Hz], mass [kg].

        Examples
        --------
        >>> from flexarm.fe import MATERIALS, TetMesh
        >>> from flexarm.reduction import CylinderRegion, reduce_part
        >>> mesh = TetMesh.box((0.4, 0.04, 0.04), (8, 2, 2))
        >>> ends = [CylinderRegion(n, (x, 0.02, 0.02), (1, 0, 0), 0.0, 0.04, 1e-6)
        ...         for n, x in (("a", 0.0), ("b", 0.4))]
        >>> reduce_part(mesh, MATERIALS["steel"], ends, "rbe2", "cb", 4)
        Superelement(cb, rbe2, 16 DOF: interfaces a 6, b 6; 4 modal, fixed-interface 2124, \
2261, 5299, … Hz, mass 5.024 kg)
        """
        n_if = len(self.interface_names)
        counts = np.bincount(np.asarray(self.node_interface, dtype=np.int64).ravel(),
                             minlength=n_if)[:n_if] * self.dofs_per_node
        pairs = [f"{n} {c}" for n, c in zip(self.interface_names, counts.tolist(), strict=True)]
        freqs = ", ".join(figure(f) for f in np.asarray(self.freq_hz)[:3])
        more = ", …" if self.n_modes > 3 else ""
        modes = f"; {self.n_modes} modal" + (f", fixed-interface {freqs}{more} Hz"
                                             if self.n_modes else "")
        return (f"Superelement({self.method}, {self.coupling}, {self.n_dofs} DOF: interfaces "
                f"{names(pairs)}{modes}, mass {self.mass:.4g} kg)")

    @classmethod
    def load(cls, path, file_format: str | None = None) -> Superelement:
        """Read a superelement file in any registered format (HDF5, NPZ, a Matrix Market
        bundle, DMIG), through :func:`flexarm.reduction.formats.read`, the reader of
        ``flexarm show`` and ``flexarm convert``.

        Examples
        --------
        >>> import tempfile, pathlib
        >>> from flexarm.fe import MATERIALS, TetMesh
        >>> from flexarm.reduction import CylinderRegion, formats, reduce_part
        >>> mesh = TetMesh.box((0.4, 0.04, 0.04), (4, 1, 1))
        >>> ends = [CylinderRegion(n, (x, 0.02, 0.02), (1, 0, 0), 0.0, 0.04, 1e-6)
        ...         for n, x in (("a", 0.0), ("b", 0.4))]
        >>> se = reduce_part(mesh, MATERIALS["steel"], ends, "rbe2", "cb", 2)
        >>> path = formats.write(pathlib.Path(tempfile.mkdtemp()) / "bar.npz", se)
        >>> bool((Superelement.load(path).K == se.K).all())
        True
        """
        return _READER["read"](path, file_format)

    # ----------------------------------------------------------------- sizes
    @property
    def n_dofs(self) -> int:
        return int(self.K.shape[0])

    @property
    def n_boundary(self) -> int:
        """Boundary (interface) DOFs, first in the DOF order."""
        return int(len(self.node_positions) * self.dofs_per_node)

    @property
    def n_modes(self) -> int:
        return int(len(self.freq_hz))

    @property
    def mass_properties(self) -> MassProperties:
        return MassProperties(float(self.mass), np.asarray(self.center_of_mass),
                              np.asarray(self.inertia))

    # -------------------------------------------------------------- recovery
    def expand(self, q) -> FloatArray:
        """(n_nodes, 3) full-field displacement [m] from reduced coordinates ``q`` (n,).

        Raises ``ValueError`` when the superelement carries no recovery matrix.
        """
        if self.T is None:
            raise ValueError("this superelement has no recovery matrix T")
        q = np.asarray(q, dtype=np.float64)
        if q.shape != (self.n_dofs,):
            raise ValueError(f"q must have shape ({self.n_dofs},), got {q.shape}")
        return (self.T @ q).astype(np.float64).reshape(-1, 3)


def reduced_rigid_modes(node_positions: FloatArray, dofs_per_node: int, n_dofs: int,
                        ref=(0.0, 0.0, 0.0)) -> FloatArray:
    """(n_dofs, 6) reduced coordinates of the 6 rigid motions about ``ref`` [m].

    Boundary node ``k`` moves as ``rigid_transport(p_k - ref)`` (its rotation equals the
    body's); modal coordinates stay zero because constraint modes carry rigid motion.
    """
    pos = np.asarray(node_positions, dtype=float)
    R = np.zeros((len(pos), 6, 6))
    R[:, :3] = rigid_transport(pos - np.asarray(ref, dtype=float))
    R[:, 3:, 3:] = np.eye(3)
    out = np.zeros((n_dofs, 6))
    nb = len(pos) * dofs_per_node
    out[:nb] = R[:, :dofs_per_node].reshape(nb, 6)
    return out


def matrix_mass_properties(M, rigid_modes: FloatArray, ref=(0.0, 0.0, 0.0)) -> MassProperties:
    """Mass, centre of mass and inertia contained in a mass matrix.

    Parameters
    ----------
    M : (n, n) sparse or dense
    rigid_modes : (n, 6) float
        The rigid motions (u then theta about ``ref``) in the coordinates of ``M``.

    Examples
    --------
    >>> mp = matrix_mass_properties(2.0 * np.eye(3), np.eye(3, 6), (0, 0, 0))
    >>> mp.mass
    2.0
    """
    R = np.asarray(rigid_modes, dtype=float)
    Mr = R.T @ (M @ R)
    Mr = 0.5 * (Mr + Mr.T)
    m = float(Mr[0, 0])
    # M_theta_u = m S(c - ref): read the offset from the skew block.
    S = Mr[3:, :3] / m
    c = np.array([S[2, 1], S[0, 2], S[1, 0]])
    inertia = Mr[3:, 3:] + m * S @ S
    return MassProperties(m, np.asarray(ref, dtype=float) + c, 0.5 * (inertia + inertia.T))


# ------------------------------------------------------------- flat layout for files
SCALAR_FIELDS = {"coupling": str, "method": str, "input_hash": str, "units": str,
            "dofs_per_node": int, "version": int, "mass": float}


def to_arrays(se: Superelement) -> dict:
    """Flat ``{name: value}`` of every field (arrays, scalars, list of names)."""
    out = {}
    for f in fields(se):
        v = getattr(se, f.name)
        if v is None:
            continue
        out[f.name] = list(v) if f.name == "interface_names" else v
    return out


def from_arrays(d: dict, source: str) -> Superelement:
    """Build and check a :class:`Superelement` read from ``source`` (file name for errors).

    Raises :class:`ReadError` naming ``source`` on a wrong version, missing fields, bad
    shapes, or matrices no free link has
    (:func:`~flexarm.reduction.matrix_checks.check_matrices`: non-finite, asymmetric, M
    not positive definite, K indefinite or without exactly six rigid-body modes, a mass
    other than the file's).
    """
    version = d.get("version")
    if version is None:
        raise ReadError(f"{source}: not a flexarm superelement (no format version)")
    if int(version) != FORMAT_VERSION:
        raise ReadError(f"{source}: superelement format version {int(version)} is not "
                        f"supported (this flexarm reads version {FORMAT_VERSION})")
    required = [f.name for f in fields(Superelement) if f.name not in _OPTIONAL]
    missing = [k for k in required if k not in d]
    if missing:
        raise ReadError(f"{source}: missing field(s) {', '.join(missing)}")
    kw = {}
    for f in fields(Superelement):
        if f.name not in d:
            continue
        v = d[f.name]
        if f.name in SCALAR_FIELDS:
            v = SCALAR_FIELDS[f.name](v.item() if isinstance(v, np.ndarray) else v)
        elif f.name == "interface_names":
            v = tuple(str(s) for s in v)
        else:
            v = np.asarray(v)
        kw[f.name] = v
    K, M = kw["K"], kw["M"]
    if K.ndim != 2 or K.shape[0] != K.shape[1] or M.shape != K.shape:
        raise ReadError(f"{source}: K and M must be square and of equal shape, got "
                        f"{K.shape} and {M.shape}")
    n_b = len(kw["node_positions"]) * kw["dofs_per_node"]
    if n_b + len(kw["freq_hz"]) != K.shape[0]:
        raise ReadError(f"{source}: {n_b} boundary DOFs + {len(kw['freq_hz'])} modes do not "
                        f"match K of shape {K.shape}")
    n_if = len(kw["interface_names"])
    shapes = {"interface_positions": (n_if, 3), "interface_frames": (n_if, 3, 3),
              "center_of_mass": (3,), "inertia": (3, 3),
              "node_positions": (len(kw["node_positions"]), 3)}
    for key, shape in shapes.items():
        if kw[key].shape != shape:
            raise ReadError(f"{source}: {key} must have shape {shape}, got {kw[key].shape}")
    if "T" in kw and (kw["T"].ndim != 2 or kw["T"].shape[1] != K.shape[0]):
        raise ReadError(f"{source}: recovery matrix T must have {K.shape[0]} columns, "
                        f"got shape {kw['T'].shape}")
    rigid = reduced_rigid_modes(kw["node_positions"], kw["dofs_per_node"], K.shape[0])
    check_matrices(K, M, rigid, kw["mass"], source)
    return Superelement(**kw)
