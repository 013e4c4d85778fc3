# ruff: noqa: T201 - a benchmark prints its figures
"""Benchmark: Tet4 and Tet10 K+M assembly, ours against scikit-fem, same mesh, same run.

Each variant runs in its own subprocess, so the peak resident memory of one does not
hide in another's; the parent prints seconds (best of ``--repeat``), elements per
second, the peak RSS above the worker's start, and the scikit-fem / ours time ratio.
Before timing, a small mesh checks that our K and M equal scikit-fem's after mapping
the DOFs (scikit-fem's ``ElementVector`` interleaves components like we do, but numbers
Tet10 edge DOFs after all vertex DOFs, in its own edge order).  Not a test.

scikit-fem runs twice: with its default quadrature (order 2p, which over-integrates K)
and as an expert configures it, with the exact orders: K on ``intorder=0`` (1 point) for
Tet4 and ``intorder=2`` (4 points) for Tet10, M on the default (exact for P1 x P1 and
P2 x P2); the check shows those matrices equal ours too.  ``x bound`` is each run's
distance to the memory-bandwidth bound: its wall time over the time to write the CSR
arrays of K and M once (values 8 bytes, column indices 4, row pointers) at the copy
bandwidth measured in the same run (``numpy.copyto`` of 512 MB).

    python benchmarks/assembly.py                 # ~100k tets, Tet4 and Tet10, with skfem
    python benchmarks/assembly.py --quick         # ~12k tets, seconds
    python benchmarks/assembly.py --tets 300000 --no-skfem
    python benchmarks/assembly.py --mesh box      # force the perturbed box

Mesh: ``--mesh auto`` (default) uses the demo arm's lower-arm link meshed by fTetWild
(edge ``LINK_SIZE``) when that mesh is in the tetrahedralisation cache, else a randomly
perturbed structured box of about ``--tets`` elements; ``--mesh link`` meshes the link
(about a minute the first time, cached after).  The Tet10 mesh is the Tet4 mesh with
straight mid-edge nodes, so both orders use the same elements.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

#: fTetWild target edge of the demo lower-arm link [m]: 99,232 tets, 28,852 nodes.
LINK_SIZE = 0.010
LINK_PART = "lower_arm.stl"
MATERIAL = "steel"


# ------------------------------------------------------------------------ meshes
def perturbed_box(n_tets: int, seed: int = 0):
    """A 5:1:1 box of about ``n_tets`` Kuhn tets, interior nodes moved by up to 20 %."""
    from flexarm.fe import TetMesh

    nx = max(2, round((n_tets / 6 * 25) ** (1 / 3)))
    ny = max(1, round(nx / 5))
    nz = max(1, round(n_tets / 6 / nx / ny))
    base = TetMesh.box((1.0, 0.2, 0.2), (nx, ny, nz))
    h = np.array([1.0 / nx, 0.2 / ny, 0.2 / nz])
    lo, hi = base.bounds()
    inner = np.all((base.points > lo + 1e-9) & (base.points < hi - 1e-9), axis=1)
    jitter = np.random.default_rng(seed).uniform(-0.2, 0.2, base.points.shape) * h
    points = base.points + jitter * inner[:, None]
    return TetMesh(points, base.tets), f"perturbed box {nx}x{ny}x{nz} (interior nodes +-20 %)"


def link_mesh(allow_meshing: bool, size: float = LINK_SIZE):
    """The fTetWild Tet4 mesh of the demo lower-arm link (from the cache), or None.

    Without ``allow_meshing`` it is only returned when already cached (no fTetWild run).
    """
    try:
        from flexarm.meshes import load_surface, tetrahedralize
        from flexarm.meshes.tet_cache import cached_mesh, tet_cache_key
        from flexarm.robot.demo_arm import demo_robot_path
    except ImportError:
        return None
    stl = Path(demo_robot_path()).parent / "meshes" / LINK_PART
    if not stl.exists():
        return None
    surface = load_surface(stl, units="m")
    key = tet_cache_key(np.asarray(surface.vertices, dtype=np.float64),
                        np.asarray(surface.faces, dtype=np.int64), size, True, 1)
    mesh = cached_mesh(key)
    if mesh is None and allow_meshing:
        mesh = tetrahedralize(surface, size=size, order=1, cache=True, name=LINK_PART)
    if mesh is None:
        return None
    return mesh, f"demo lower-arm link ({LINK_PART}), fTetWild edge {size} m, cached"


# ------------------------------------------------------------------------ workers
def _rss_kb(field: str) -> int:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1])
    return 0


def _skfem_setup(mesh, order: int, exact: bool = False):
    from skfem import Basis, BilinearForm, ElementTetP1, ElementTetP2, ElementVector, MeshTet
    from skfem.helpers import dot
    from skfem.models.elasticity import linear_elasticity

    from flexarm.fe import MATERIALS

    mat = MATERIALS[MATERIAL]
    sk_mesh = MeshTet(np.ascontiguousarray(mesh.points.T), np.ascontiguousarray(mesh.tets[:, :4].T))
    element = ElementVector(ElementTetP1() if order == 1 else ElementTetP2())
    rho = mat.rho

    @BilinearForm
    def mass(u, v, w):
        return rho * dot(u, v)

    def run():
        basis = Basis(sk_mesh, element)
        # exact: grad u . grad v is P0 (Tet4) or P2 (Tet10)
        basis_k = Basis(sk_mesh, element, intorder=2 * order - 2) if exact else basis
        K = linear_elasticity(mat.lame_lambda, mat.lame_mu).assemble(basis_k)
        M = mass.assemble(basis)
        return K, M, basis

    return run


def _ours_setup(mesh, order: int):
    from flexarm.fe import MATERIALS, assemble

    mat = MATERIALS[MATERIAL]
    m = mesh if order == 1 else mesh.to_tet10()

    def run():
        K, M = assemble(m, mat)
        return K, M, None

    return run


def worker(args) -> None:
    """One variant in this process: print a JSON line with its figures."""
    from flexarm.fe import TetMesh

    data = np.load(args.mesh_file)
    mesh = TetMesh(data["points"], data["tets"])
    if args.worker == "ours":
        run = _ours_setup(mesh, args.order)
    else:
        run = _skfem_setup(mesh, args.order, exact=args.worker == "skfem-exact")
    start_kb = _rss_kb("VmRSS")
    times = []
    for _ in range(args.repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        K, M, _ = run()
        times.append((time.perf_counter() - t0, time.process_time() - c0))
        n_dof, nnz, nnz_m = K.shape[0], K.nnz, M.nnz
        del K, M
    peak_mb = (_rss_kb("VmHWM") - start_kb) / 1024.0
    wall, cpu = min(times)
    print(json.dumps({"wall": wall, "cpu": cpu, "peak_mb": peak_mb, "n_dof": n_dof, "nnz": nnz,
                      "nnz_m": nnz_m, "all": [t[0] for t in times]}))


def run_worker(which: str, mesh_file: str, order: int, repeat: int) -> dict:
    cmd = [sys.executable, __file__, "--worker", which, "--mesh-file", mesh_file,
           "--order", str(order), "--repeat", str(repeat)]
    out = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if out.returncode != 0:
        raise RuntimeError(f"{which} Tet{4 if order == 1 else 10} worker failed:\n{out.stderr}")
    return json.loads(out.stdout.strip().splitlines()[-1])


# ------------------------------------------------------------------------ check
def dof_map_to_skfem(mesh, basis) -> np.ndarray:
    """For each of our DOFs (3 node + c), the scikit-fem DOF of the same node and component."""
    n_corner = int(mesh.tets[:, :4].max()) + 1
    perm = np.zeros(mesh.n_dofs, dtype=np.int64)
    corner = np.unique(mesh.tets[:, :4])
    perm[3 * corner[:, None] + np.arange(3)] = basis.nodal_dofs[:, corner].T
    if mesh.order == 2:
        from flexarm.fe import TET10_EDGES

        ends = np.sort(mesh.tets[:, TET10_EDGES], axis=2).reshape(-1, 2)
        mids = mesh.tets[:, 4:].reshape(-1)
        sk_edges = np.sort(basis.mesh.edges.T, axis=1)
        key = sk_edges[:, 0] * n_corner + sk_edges[:, 1]
        order = np.argsort(key)
        pos = order[np.searchsorted(key[order], ends[:, 0] * n_corner + ends[:, 1])]
        perm[3 * mids[:, None] + np.arange(3)] = basis.edge_dofs[:, pos].T
    return perm


def check_against_skfem(mesh) -> list[str]:
    """Relative max difference of our K, M and scikit-fem's on ``mesh`` (both orders,
    default and exact quadrature)."""
    lines = []
    for order, exact in ((1, False), (1, True), (2, False), (2, True)):
        K, M, _ = _ours_setup(mesh, order)()
        Ks, Ms, basis = _skfem_setup(mesh, order, exact)()
        ours_mesh = mesh if order == 1 else mesh.to_tet10()
        p = dof_map_to_skfem(ours_mesh, basis)
        Ks, Ms = Ks.tocsr()[p][:, p], Ms.tocsr()[p][:, p]
        dk = abs(K - Ks).max() / abs(K).max()
        dm = abs(M - Ms).max() / abs(M).max()
        ok = "OK" if max(dk, dm) < 1e-10 else "MISMATCH"
        lines.append(f"  Tet{4 if order == 1 else 10:<2d} {K.shape[0]:6d} DOF, skfem "
                     f"{'exact' if exact else 'default'} quadrature: "
                     f"max|K - K_skfem|/max|K| = {dk:.1e}, M: {dm:.1e}  {ok}")
    return lines


def copy_bandwidth(n_bytes: int = 512 * 2**20, repeat: int = 5) -> float:
    """Memory copy bandwidth [bytes/s]: bytes copied per second, best of ``repeat``."""
    src = np.ones(n_bytes // 8)
    dst = np.empty_like(src)
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        np.copyto(dst, src)
        best = min(best, time.perf_counter() - t)
    return n_bytes / best


def csr_bytes(n_dof: int, nnz_k: int, nnz_m: int) -> int:
    """Bytes of the CSR arrays of K and M (float64 values, int32 indices and pointers)."""
    return 12 * (nnz_k + nnz_m) + 2 * 4 * (n_dof + 1)


# ------------------------------------------------------------------------ main
def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tets", type=int, default=100_000, help="box size (default 100000)")
    ap.add_argument("--quick", action="store_true", help="~12k tets, box")
    ap.add_argument("--mesh", choices=("auto", "link", "box"), default="auto")
    ap.add_argument("--repeat", type=int, default=3, help="repeats of our assembly (best)")
    ap.add_argument("--skfem-repeat", type=int, default=1)
    ap.add_argument("--no-skfem", action="store_true")
    ap.add_argument("--worker", choices=("ours", "skfem", "skfem-exact"),
                    help=argparse.SUPPRESS)
    ap.add_argument("--mesh-file", help=argparse.SUPPRESS)
    ap.add_argument("--order", type=int, default=1, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker:
        worker(args)
        return 0

    if args.quick:
        args.tets, args.mesh = 12_000, "box"
    found = None
    if args.mesh != "box" and args.tets == 100_000:
        found = link_mesh(allow_meshing=args.mesh == "link")
    mesh, what = found if found else perturbed_box(args.tets)
    have_skfem = not args.no_skfem
    if have_skfem:
        try:
            import skfem  # noqa: F401
        except ImportError:
            print("scikit-fem not installed: ours only")
            have_skfem = False

    print(f"date {time.strftime('%Y-%m-%d %H:%M')}, {os.cpu_count()} cores, "
          f"load average {os.getloadavg()[0]:.1f} at start")
    print(f"mesh: {what}: {mesh.n_tets} tets, {mesh.n_nodes} Tet4 nodes")
    from flexarm.fe import rows

    print("ours: " + ("compiled row assembly (flexarm.fe._rows)" if rows.available()
                      else "NumPy path (the C extension flexarm.fe._rows is not built)"))
    if have_skfem:
        small, small_what = perturbed_box(600, seed=1)
        print(f"check on a small {small_what}, {small.n_tets} tets:")
        for line in check_against_skfem(small):
            print(line)

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        mesh_file = os.path.join(tmp, "mesh.npz")
        np.savez(mesh_file, points=mesh.points, tets=mesh.tets)
        for order in (1, 2):
            name = f"Tet{4 if order == 1 else 10}"
            ours = run_worker("ours", mesh_file, order, args.repeat)
            rows.append((name, "flexarm", ours))
            if have_skfem:
                sk = run_worker("skfem-exact", mesh_file, order, args.skfem_repeat)
                rows.append((name, "skfem exact", sk))
                sk = run_worker("skfem", mesh_file, order, args.skfem_repeat)
                rows.append((name, "skfem default", sk))
    bandwidth = copy_bandwidth()

    print(f"\ncopy bandwidth {bandwidth / 1e9:.1f} GB/s (numpy.copyto, 512 MB)")
    print(f"{'K+M':6s} {'code':13s} {'DOF':>8s} {'nnz(K)':>10s} {'wall s':>8s} {'1st s':>7s} "
          f"{'cpu s':>7s} {'elem/s':>10s} {'peak MB':>8s} {'skfem/ours':>10s} {'(1st)':>6s} "
          f"{'x bound':>8s} {'(1st)':>7s}")
    ours_time, ours_first = {}, {}
    for name, code, r in rows:
        if code == "flexarm":
            ours_time[name], ours_first[name] = r["wall"], r["all"][0]
        ratio = f"{r['wall'] / ours_time[name]:.1f}x" if code != "flexarm" else ""
        first = f"{r['all'][0] / ours_first[name]:.1f}x" if code != "flexarm" else ""
        bound = csr_bytes(r["n_dof"], r["nnz"], r.get("nnz_m", r["nnz"])) / bandwidth
        print(f"{name:6s} {code:13s} {r['n_dof']:8d} {r['nnz']:10d} {r['wall']:8.2f} "
              f"{r['all'][0]:7.2f} {r['cpu']:7.2f} {mesh.n_tets / r['wall']:10.3g} "
              f"{r['peak_mb']:8.0f} {ratio:>10s} {first:>6s} {r['wall'] / bound:7.1f}x "
              f"{r['all'][0] / bound:6.1f}x")
    print("wall s: best of the repeats; 1st s: the first call in a fresh process, whose "
          "fresh pages cost extra\nin this VM (every skfem run here is a first call); "
          "x bound (1st): wall (first call) over the CSR-write time")
    print(f"load average {os.getloadavg()[0]:.1f} at end (2 shared cores: wall times are noisy; "
          "ratios come from the same run)")
    print("targets: Tet4 >= 20x, Tet10 >= 60x scikit-fem with exact quadrature, first call "
          "included; <= 30x the bound")
    return 0


if __name__ == "__main__":
    sys.exit(main())
